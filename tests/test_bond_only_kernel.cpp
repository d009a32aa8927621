// The bond-only kernel (bodies/symmetric/bond_only.hpp) and its fused damage step: on perturbed
// lattice blocks and jittered clouds with randomly failed bonds, 2D and 3D, for the CKPD law
// with bonds only, its Seth-Hill and energy-consistent forms and the PMB model, both damage
// rules, one and two OpenMP threads:
// - forces and energies equal the reference kernel to 1e-12 of their largest value, and the
//   general path of the symmetric kernel (the body without its bond table) bit for bit;
// - fail_bonds_and_compute_internal_force equals fail_overstretched_bonds followed by the
//   kernel bit for bit: the same bonds fail, the same dissipated energy, the same forces;
// - it is deterministic for a fixed thread count.
#include <omp.h>

#include <catch2/catch.hpp>
#include <random>
#include <string>
#include <vector>

#include "bodies/body.hpp"
#include "bodies/damage.hpp"
#include "bodies/force_model_kernels.hpp"
#include "bodies/pmb_model.hpp"
#include "bodies/symmetric_kernel.hpp"
#include "kernel_comparison.hpp"

using namespace kernel_comparison;

namespace {

struct Variant {
  std::string label;
  int dimension;
  double jitter;
  int nx, ny, nz;
  int model;  // 0 CKPD, 1 CKPD Seth-Hill m = -1/2, 2 CKPD energy-consistent, 3 PMB
  ckpd::DamageRule rule;
  double m = kM;
};

const std::vector<Variant>& variants() {
  using R = ckpd::DamageRule;
  static const std::vector<Variant> v = {
      {"3D lattice, CKPD", 3, 0.0, 7, 7, 6, 0, R::centre_bonds},
      {"3D jittered cloud, CKPD, all edges", 3, 0.25, 7, 6, 6, 0, R::all_edges},
      {"3D jittered cloud, Seth-Hill", 3, 0.25, 6, 6, 6, 1, R::centre_bonds},
      {"3D jittered cloud, energy-consistent", 3, 0.25, 6, 7, 6, 2, R::all_edges},
      {"3D lattice, PMB", 3, 0.0, 7, 6, 6, 3, R::centre_bonds},
      {"3D jittered cloud, PMB, m = 3.7", 3, 0.2, 7, 6, 6, 3, R::all_edges, 3.7},
      {"2D lattice, CKPD", 2, 0.0, 17, 15, 1, 0, R::centre_bonds},
      {"2D jittered cloud, CKPD, all edges", 2, 0.3, 17, 15, 1, 0, R::all_edges},
      {"2D jittered cloud, energy-consistent", 2, 0.3, 16, 15, 1, 2, R::centre_bonds},
      {"2D jittered cloud, PMB, m = 9.3", 2, 0.2, 21, 20, 1, 3, R::all_edges, 9.3},
  };
  return v;
}

// A bond-only body of the variant: C1 of the material, C2 = C3 = 0.
Body make(const Variant& v, std::mt19937& rng, double critical_stretch) {
  ckpd::InteractionConstants c = ckpd::interaction_constants(
      v.dimension, kE, 0.25, v.dimension == 2 ? PlaneMode::stress : PlaneMode::none, v.m * kDx);
  c.c2 = c.c3 = 0;
  BodyDefinition d = block(v.dimension, v.nx, v.ny, v.nz, c, v.jitter, rng, v.m);
  d.critical_stretch = critical_stretch;
  d.damage_rule = v.rule;
  if (v.model == 1) d.strain_measure = -0.5;
  if (v.model == 2) d.force_form = ckpd::ForceForm::energy_consistent;
  if (v.model == 3) d.model = &ckpd::kernels_of<ckpd::PmbModel>();
  Body body = ckpd::make_body(std::move(d));
  REQUIRE(body.upper_bonds != nullptr);
  return body;
}

}  // namespace

TEST_CASE("bond-only kernel equals the reference kernel and the general path, bit for bit",
          "[bond_only_kernel]") {
  ThreadCountGuard guard;
  std::mt19937 rng(41);
  for (const Variant& v : variants()) {
    Body body = make(v, rng, 1.0);
    perturb(body, 0.02, rng);
    fail_bonds(body, 0.1, rng);
    Body general = body;
    general.upper_bonds.reset();  // the general path of the symmetric kernel
    for (const int threads : {1, 2}) {
      INFO(v.label << ", threads " << threads);
      const Difference d = compare_kernels(body, threads);
      CHECK(d.force <= 1e-12);
      CHECK(d.energy <= 1e-12);
      const ckpd::SymmetricKernelStats s = ckpd::compute_internal_force_symmetric(general, true);
      const ckpd::SymmetricKernelStats f = ckpd::compute_internal_force_symmetric(body, true);
      CHECK(f.bonds == s.bonds);
      CHECK(body.force_density == general.force_density);
      CHECK(body.strain_energy_density == general.strain_energy_density);
      // Without energy too (another instantiation).
      ckpd::compute_internal_force_symmetric(general, false);
      ckpd::compute_internal_force_symmetric(body, false);
      CHECK(body.force_density == general.force_density);
    }
  }
}

TEST_CASE("the bond-only kernel's fused damage step equals the separate pass, bit for bit",
          "[bond_only_kernel]") {
  ThreadCountGuard guard;
  std::mt19937 rng(42);
  for (const Variant& v : variants()) {
    for (const bool protect : {false, true}) {
      Body body = make(v, rng, 1.0);
      perturb(body, 0.02, rng);
      fail_bonds(body, 0.05, rng);
      std::uniform_real_distribution<double> u(-1, 1);
      for (Vec3& x : body.velocity) x = Vec3(u(rng), u(rng), v.dimension == 3 ? u(rng) : 0.0);
      if (protect) {
        body.no_failure.assign(body.size(), 0);
        for (std::size_t i = 0; i < body.size(); i += 5) body.no_failure[i] = 1;
      }
      // The critical stretch is one bond's own stretch (as the failure test computes it): that
      // bond is at the threshold exactly and must survive, in both paths.
      const std::size_t i0 = body.size() / 2, k0 = body.family.offset[i0];
      const std::uint32_t j0 = body.family.neighbour[k0];
      body.critical_stretch =
          ckpd::bond_stretch(body.reference_position[j0] - body.reference_position[i0],
                             body.displacement[j0] - body.displacement[i0]);
      for (const int threads : {1, 2}) {
        for (const bool energy : {true, false}) {
          INFO(v.label << (protect ? ", no-failure points" : "") << ", threads " << threads
                       << (energy ? ", with energy" : ""));
          omp_set_num_threads(threads);
          Body separate = body, fused = body, again = body;
          const ckpd::FailureUpdate a = ckpd::fail_overstretched_bonds(separate, 3e-7);
          const ckpd::SymmetricKernelStats sa =
              ckpd::compute_internal_force_symmetric(separate, energy);
          ckpd::FailureUpdate b, c;
          const ckpd::SymmetricKernelStats sb =
              ckpd::fail_bonds_and_compute_internal_force(fused, energy, 3e-7, b);
          ckpd::fail_bonds_and_compute_internal_force(again, energy, 3e-7, c);
          REQUIRE(a.failed > 0);
          CHECK(b.failed == a.failed);
          CHECK(b.dissipated == a.dissipated);
          CHECK(sb.bonds == sa.bonds);
          CHECK(fused.bond_intact == separate.bond_intact);
          CHECK(fused.bond_intact[k0] == body.bond_intact[k0]);  // at the threshold: kept
          CHECK(fused.force_density == separate.force_density);
          if (energy) CHECK(fused.strain_energy_density == separate.strain_energy_density);
          // Deterministic: a second run from the same state gives the same bits.
          CHECK(c.failed == b.failed);
          CHECK(c.dissipated == b.dissipated);
          CHECK(again.bond_intact == fused.bond_intact);
          CHECK(again.force_density == fused.force_density);
          // The next step fails nothing more at the same state, and the flags it keeps between
          // calls are clear: the forces are the surviving bonds' again.
          ckpd::FailureUpdate next;
          ckpd::fail_bonds_and_compute_internal_force(fused, energy, 3e-7, next);
          CHECK(next.failed == 0);
          CHECK(next.dissipated == 0);
          CHECK(fused.force_density == separate.force_density);
        }
      }
    }
  }
}
