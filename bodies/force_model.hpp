#pragma once
// The seam between a body and its force model. A model is one type (CkpdModel in
// ckpd_model.hpp, PmbModel in pmb_model.hpp) holding the law of each of its interaction
// families and its damage rule; the kernels are templates over it (force_model_kernels.hpp),
// instantiated once per model. A body holds the table of its model's instantiations and the
// kernels are called through it once per body and evaluation, never per interaction.
#include <cstddef>
#include <cstdint>

namespace ckpd {

struct Body;
class FamilyScratch;
class SymmetricKernelWorkspace;
struct SymmetricKernelStats;
struct PointResult;
struct PointCensus;
struct FailureUpdate;
struct LinearOperator;

struct ForceModelKernels {
  const char* name;  // as a material's `model:` names it
  // Every set once (symmetric_kernel.hpp): body.force_density, with energy also
  // body.strain_energy_density.
  SymmetricKernelStats (*symmetric)(Body& body, bool with_energy,
                                    SymmetricKernelWorkspace& workspace);
  // One point's own family (point_kernel.hpp): its force density and energies.
  PointResult (*point)(const Body& body, std::size_t i, FamilyScratch& scratch);
  // One point's interaction counts and stiffness-bound matrices (census.hpp); the scratch holds
  // the point's whole family.
  PointCensus (*census)(const Body& body, const FamilyScratch& scratch);
  // The damage rule (bond_failure.hpp): fail the bonds it breaks now, with and without booking
  // the energy they take.
  std::size_t (*update_failure)(Body& body);
  FailureUpdate (*fail_and_book)(Body& body, double half_drift);
  // Null, or what make_body calls last: a model without a per-set census (state_based_model.hpp)
  // sets its own constants and stiffness bound here.
  void (*prepare)(Body& body);
  // Null, or the linearisation at the reference state (linear_operator.hpp) into the zeroed
  // rows of op.
  void (*linearise)(const Body& body, LinearOperator& op);
  // Null, or fail_and_book followed by symmetric (the damage step's result into failure), in
  // one pass over the bonds where the model's kernel can (bonds only: symmetric/bond_only.hpp).
  SymmetricKernelStats (*fail_and_symmetric)(Body& body, bool with_energy, double half_drift,
                                             SymmetricKernelWorkspace& workspace,
                                             FailureUpdate& failure);
};

// The CKPD model's table (the default of every body).
const ForceModelKernels& ckpd_kernels();
// The CKPD model with a Seth-Hill strain measure m != 1/2 (Body::strain_measure).
const ForceModelKernels& ckpd_seth_hill_kernels();
// The same two with ForceForm::energy_consistent (Body::force_form; ckpd_model.hpp).
const ForceModelKernels& ckpd_conservative_kernels();
const ForceModelKernels& ckpd_seth_hill_conservative_kernels();

// The table of a body's model.
const ForceModelKernels& force_model(const Body& body);

}  // namespace ckpd
