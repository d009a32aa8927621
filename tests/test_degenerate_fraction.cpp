// A body's degenerate_fraction: sets whose |A| / (L L) or |V| / (L L L) seen from the centre is
// at most f are left out. The census, the reference kernel and the symmetric kernel must make
// the same decisions for any f; a bent lattice with the slivers left out has the straight
// lattice's interaction counts and stable step.
#include <omp.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "bodies/material.hpp"
#include "bodies/symmetric_kernel.hpp"
#include "body_fixtures.hpp"
#include "reference/internal_force.hpp"

using namespace ckpd;
using namespace ckpd_test;

namespace {

constexpr double kDx = 0.001, kE = 200e9;

InteractionConstants constants(int dimension, double nu, double m) {
  return interaction_constants(dimension, kE, nu,
                               dimension == 2 ? PlaneMode::stress : PlaneMode::none, m * kDx);
}

// Largest difference between the symmetric and the reference kernel, over the largest value.
std::pair<double, double> kernel_difference(Body& body) {
  compute_internal_force(body, true);
  const std::vector<Vec3> force = body.force_density;
  const std::vector<double> energy = body.strain_energy_density;
  double fscale = 0, escale = 0;
  for (std::size_t i = 0; i < body.size(); ++i) {
    fscale = std::max(fscale, force[i].norm());
    escale = std::max(escale, std::abs(energy[i]));
  }
  compute_internal_force_symmetric(body, true);
  double df = 0, de = 0;
  for (std::size_t i = 0; i < body.size(); ++i) {
    df = std::max(df, (body.force_density[i] - force[i]).norm());
    de = std::max(de, std::abs(body.strain_energy_density[i] - energy[i]));
  }
  return {df / fscale, de / escale};
}

// A square lattice of nx x ny points bent along a circular arc of radius R (x runs along the
// arc), with volumes from the local spacing: a smoothly distorted lattice like the curved bar.
BodyDefinition bent_strip(int nx, int ny, double radius, double m, double nu) {
  BodyDefinition d = lattice_block(2, nx, ny, 1, kDx, m, constants(2, nu, m));
  const double mid = (ny - 1) * kDx / 2;
  for (std::size_t i = 0; i < d.reference_position.size(); ++i) {
    const Vec3 p = d.reference_position[i];
    const double r = radius + p.y() - mid, angle = p.x() / radius;
    d.reference_position[i] = Vec3(r * std::sin(angle), r * std::cos(angle), 0);
    d.volume[i] = kDx * kDx * r / radius;
  }
  d.cap_beta = true;
  return d;
}

}  // namespace

TEST_CASE("with a raised degenerate fraction the census and both kernels leave out the same sets",
          "[symmetric_kernel]") {
  const int threads = omp_get_max_threads();
  struct Setting {
    const char* label;
    int dimension;
    double nu, fraction;
    int nx, ny, nz;
  };
  for (const Setting s :
       {Setting{"2D, nu=0.4", 2, 0.4, 0.05, 15, 14, 1},
        Setting{"2D, nu=0.2", 2, 0.2, 0.2, 15, 14, 1}, Setting{"3D, nu=0.3", 3, 0.3, 0.02, 6, 6, 6},
        Setting{"3D, nu=0.1", 3, 0.1, 0.05, 6, 6, 5}}) {
    for (const int t : {1, 2}) {
      omp_set_num_threads(t);
      std::mt19937 rng(2024);
      BodyDefinition def = jittered_cloud(s.dimension, s.nx, s.ny, s.nz, kDx, 3.015,
                                          constants(s.dimension, s.nu, 3.015), 0.25, rng);
      const Body loose = make_body(def);
      def.degenerate_fraction = s.fraction;
      Body body = make_body(def);
      INFO(s.label << ", f = " << s.fraction << ", " << t << " thread(s)");
      // Jittered clouds have sets on both sides of f: the raised fraction must remove some.
      CHECK(body.total_two_neighbour() + body.total_three_neighbour() <
            loose.total_two_neighbour() + loose.total_three_neighbour());
      std::vector<std::uint32_t> n2, n3;
      count_interactions_symmetric(body, n2, n3);
      CHECK(n2 == body.n2);
      CHECK(n3 == body.n3);
      perturb(body, 0.05 * kDx, rng);
      std::mt19937 fail_rng(5);
      fail_random_bonds(body, 0.2, fail_rng);
      const auto [force, energy] = kernel_difference(body);
      INFO("force " << force << ", energy " << energy);
      CHECK(force <= 1e-12);
      CHECK(energy <= 1e-12);
    }
  }
  omp_set_num_threads(threads);
}

TEST_CASE("a bent lattice without its slivers has the straight lattice's counts and stable step",
          "[symmetric_kernel]") {
  // 60 x 12 points bent to a radius of 1500 dx: gentle enough that every bond of the straight
  // lattice stays within the horizon and no other comes in, yet its collinear triples become
  // slivers (|A| / (L L) about 1e-3) that stiffen it.
  const double m = 3.015, nu = 0.3;
  const Body lattice = make_body(lattice_block(2, 60, 12, 1, kDx, m, constants(2, nu, m)));
  BodyDefinition bent = bent_strip(60, 12, 1500 * kDx, m, nu);
  const Body slivers = make_body(bent);
  bent.degenerate_fraction = 0.1;  // the lattice's genuine triangles have |A| / (L L) >= 0.316
  const Body clean = make_body(bent);

  REQUIRE(slivers.bond_count() == lattice.bond_count());
  CHECK(slivers.total_two_neighbour() > lattice.total_two_neighbour());
  CHECK(clean.total_two_neighbour() == lattice.total_two_neighbour());
  CHECK(clean.n2 == lattice.n2);
  const double dt_lattice = stable_step(lattice).dt, dt_slivers = stable_step(slivers).dt,
               dt_clean = stable_step(clean).dt;
  INFO("dt lattice " << dt_lattice << ", with slivers " << dt_slivers << ", without " << dt_clean);
  CHECK(dt_slivers < 0.5 * dt_lattice);
  CHECK(dt_clean == Approx(dt_lattice).epsilon(0.01));
}

TEST_CASE("a degenerate fraction outside (0, 1) is refused", "[symmetric_kernel]") {
  BodyDefinition d = lattice_block(2, 5, 5, 1, kDx, 3.015, constants(2, 0.3, 3.015));
  d.degenerate_fraction = 0;
  CHECK_THROWS_WITH(make_body(d), Catch::Contains("degenerate fraction must be in (0, 1)"));
  d.degenerate_fraction = 1;
  CHECK_THROWS_WITH(make_body(d), Catch::Contains("degenerate fraction must be in (0, 1)"));
}
