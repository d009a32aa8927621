#pragma once
// A force model's table of kernels (force_model.hpp): every kernel template instantiated for
// Model. A model's own file defines its table with kernels_of<Model>() and nothing else.
#include "bodies/bond_failure.hpp"
#include "bodies/census.hpp"
#include "bodies/force_model.hpp"
#include "bodies/linear_operator.hpp"
#include "bodies/point_kernel.hpp"
#include "bodies/symmetric/kernel_of.hpp"

namespace ckpd {

template <class Model>
const ForceModelKernels& kernels_of() {
  static const ForceModelKernels table{
      Model::kName,
      [](Body& body, bool with_energy, SymmetricKernelWorkspace& workspace) {
        return symmetric::compute_of<Model>(body, with_energy, workspace);
      },
      [](const Body& body, std::size_t i, FamilyScratch& scratch) {
        return evaluate_point_of(Model::of(body), body, i, scratch);
      },
      [](const Body& body, const FamilyScratch& scratch) {
        return census_point_of(Model::of(body), scratch, body.degenerate_fraction);
      },
      [](Body& body) { return update_bond_failure_of(Model::of(body), body); },
      [](Body& body, double half_drift) {
        return fail_overstretched_bonds_of(Model::of(body), body, half_drift);
      },
      nullptr,
      [](const Body& body, LinearOperator& op) {
        assemble_linear_operator_of(Model::of(body), body, op);
      },
      [](Body& body, bool with_energy, double half_drift, SymmetricKernelWorkspace& workspace,
         FailureUpdate& failure) {
        return symmetric::compute_of<Model>(body, with_energy, workspace, half_drift, &failure);
      }};
  return table;
}

}  // namespace ckpd
