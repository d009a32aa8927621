// The optimised current-state stiffness bound (bodies/current_stiffness.cpp: pair quantities
// shared through a pair table, gradient norms taken as edge lengths) against the plain path
// that evaluates every set on its own (reference/current_stiffness.cpp): the same bound and the
// same shrink times to 1e-11 relative on randomly deformed bodies with random failed bonds, in
// 2D and 3D, lattice and jittered cloud, m = 0, -1/4 and -1/2, both damage rules and force
// forms, 1 and 2 threads, the sets in vector lanes and one by one; also with a set squeezed
// towards zero volume, where the bound is dominated by one set's curvature.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

#include "bodies/body.hpp"
#include "bodies/current_stiffness.hpp"
#include "kernel_comparison.hpp"
#include "reference/current_stiffness.hpp"

using namespace kernel_comparison;

namespace {

double relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
  REQUIRE(a.size() == b.size());
  double worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i] == b[i]) continue;  // also equal infinities
    if (!std::isfinite(a[i]) || !std::isfinite(b[i])) return INFINITY;
    worst = std::max(worst, std::abs(a[i] - b[i]) / std::max(std::abs(b[i]), 1e-300));
  }
  return worst;
}

void random_velocities(Body& body, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-10, 10);
  for (Vec3& v : body.velocity) v = Vec3(u(rng), u(rng), body.dimension == 3 ? u(rng) : 0.0);
}

// Evaluates the triangles and tetrahedra in vector lanes (where the build has them) or one by one
// (the loops of builds without them) while in scope.
struct LanesGuard {
  bool saved = ckpd::current_stiffness_detail::sets_in_lanes;
  explicit LanesGuard(bool lanes) { ckpd::current_stiffness_detail::sets_in_lanes = lanes; }
  ~LanesGuard() { ckpd::current_stiffness_detail::sets_in_lanes = saved; }
};

// A set's volume is computed from its lowest vertex here and from each vertex in the plain
// path: rounding of v relative to |v| differs by a few ulps times |p||q||r| / |v|, and the
// curvature r^(4m - 2) (m = -1/2: r^-4) multiplies it; measured worst 1.1e-12 on the jittered
// 3D cloud at m = -1/2.
constexpr double kTolerance = 1e-11;

}  // namespace

TEST_CASE("Current-state stiffness bound equals the plain set-by-set path", "[stable_step]") {
  ThreadCountGuard guard;
  const std::vector<Scene> scenes = {
      {"2D lattice, plane stress nu=0.4", 2, 0.4, 0.0, 9, 8, 1},
      {"2D jittered cloud, nu=0.35", 2, 0.35, 0.3, 9, 8, 1},
      {"3D lattice, nu=0.3", 3, 0.3, 0.0, 5, 5, 4, false, 2.015},
      {"3D jittered cloud, triangles and tetrahedra", 3, 0.3, 0.1, 5, 4, 4, true, 2.015},
  };
  for (const Scene& s : scenes) {
    for (const double m : {0.0, -0.25, -0.5}) {
      for (const auto form : {ckpd::ForceForm::own_family, ckpd::ForceForm::energy_consistent}) {
        for (const auto rule : {ckpd::DamageRule::centre_bonds, ckpd::DamageRule::all_edges}) {
          std::mt19937 rng(4711);
          BodyDefinition def =
              block(s.dimension, s.nx, s.ny, s.nz, constants_for(s), s.jitter, rng, s.m);
          def.strain_measure = m;
          def.inversion_penalty = 1.0;
          def.force_form = form;
          def.damage_rule = rule;
          Body body = ckpd::make_body(std::move(def));
          perturb(body, 0.08, rng);
          fail_bonds(body, 0.1, rng);
          random_velocities(body, rng);
          std::vector<double> want, want_shrink;
          ckpd::reference_ckpd_current_stiffness_bound(body, want, &want_shrink);
          for (const int threads : {1, 2}) {
            for (const bool lanes : {true, false}) {
              omp_set_num_threads(threads);
              const LanesGuard use(lanes);
              std::vector<double> got, got_shrink, got_plain;
              ckpd::ckpd_current_stiffness_bound(body, got, &got_shrink);
              ckpd::ckpd_current_stiffness_bound(body, got_plain);
              INFO(s.label << ", m = " << m << ", energy_consistent "
                           << (form == ckpd::ForceForm::energy_consistent) << ", all_edges "
                           << (rule == ckpd::DamageRule::all_edges) << ", threads " << threads
                           << ", lanes " << lanes);
              CHECK(relative_difference(got, want) <= kTolerance);
              CHECK(relative_difference(got_plain, want) <= kTolerance);
              CHECK(relative_difference(got_shrink, want_shrink) <= kTolerance);
            }
          }
        }
      }
    }
  }
}

TEST_CASE("Current-state stiffness bound equals the plain path with a set squeezed flat",
          "[stable_step]") {
  // One point of a 3D lattice pushed towards the plane of three of its neighbours: the sets
  // through it approach zero volume and their curvature (1 - log r) / r^2 dominates the bound.
  std::mt19937 rng(5);
  const Scene s{"3D lattice", 3, 0.3, 0.0, 4, 4, 4, false, 2.015};
  BodyDefinition def = block(3, 4, 4, 4, constants_for(s), 0.0, rng, s.m);
  def.strain_measure = 0.0;
  Body body = ckpd::make_body(std::move(def));
  perturb(body, 0.01, rng);
  const std::size_t centre = 21;  // interior: (1, 1, 1)
  for (const double squeeze : {0.5, 0.9, 0.99}) {
    body.displacement[centre].z() = -squeeze * kDx;
    std::vector<double> want;
    ckpd::reference_ckpd_current_stiffness_bound(body, want);
    for (const bool lanes : {true, false}) {
      const LanesGuard use(lanes);
      std::vector<double> got;
      ckpd::ckpd_current_stiffness_bound(body, got);
      INFO("squeeze " << squeeze << ", lanes " << lanes << ": bound " << got[centre] << " (at rest "
                      << body.stiffness_bound[centre] << ")");
      CHECK(got[centre] > body.stiffness_bound[centre]);
      CHECK(relative_difference(got, want) <= kTolerance);
    }
  }
}

TEST_CASE("Current-state stiffness bound is bitwise reproducible at a given thread count",
          "[stable_step]") {
  ThreadCountGuard guard;
  std::mt19937 rng(11);
  const Scene s{"3D jittered cloud", 3, 0.3, 0.1, 5, 4, 4, true, 2.015};
  BodyDefinition def = block(3, s.nx, s.ny, s.nz, constants_for(s), s.jitter, rng, s.m);
  def.strain_measure = -0.5;
  def.force_form = ckpd::ForceForm::energy_consistent;
  Body body = ckpd::make_body(std::move(def));
  perturb(body, 0.08, rng);
  fail_bonds(body, 0.1, rng);
  random_velocities(body, rng);
  for (const int threads : {1, 2}) {
    omp_set_num_threads(threads);
    std::vector<double> first, second, first_shrink, second_shrink;
    ckpd::ckpd_current_stiffness_bound(body, first, &first_shrink);
    ckpd::ckpd_current_stiffness_bound(body, second, &second_shrink);
    CHECK(first == second);
    CHECK(first_shrink == second_shrink);
  }
}
