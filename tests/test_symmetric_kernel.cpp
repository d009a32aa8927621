// The once-per-interaction kernel (bodies/symmetric_kernel.hpp) against the reference kernel
// compute_internal_force: forces and energies to 1e-12 of their largest value, on perturbed
// lattice blocks and jittered clouds with randomly failed bonds, in 2D (C2 < 0 and C2 > 0) and
// 3D (C3 > 0 and C3 < 0), with one and two OpenMP threads; per-vertex degeneracy decisions
// (counts equal body.n2 / body.n3, hand-made sets that are degenerate from some vertices only);
// determinism for a fixed thread count.
#include <omp.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "bodies/body.hpp"
#include "bodies/material.hpp"
#include "bodies/symmetric_kernel.hpp"
#include "kernel_comparison.hpp"
#include "reference/internal_force.hpp"

using namespace kernel_comparison;

TEST_CASE("symmetric kernel equals the reference kernel on perturbed, damaged bodies",
          "[symmetric_kernel]") {
  ThreadCountGuard guard;
  const std::vector<Scene> scenes = {
      {"2D lattice, plane stress nu=0.2 (C2<0)", 2, 0.2, 0.0, 17, 15, 1},
      {"2D lattice, plane stress nu=0.4 (C2>0)", 2, 0.4, 0.0, 17, 15, 1},
      {"2D jittered cloud, nu=0.4", 2, 0.4, 0.3, 17, 15, 1},
      {"2D jittered cloud, nu=0.2", 2, 0.2, 0.3, 17, 15, 1},
      {"3D lattice, nu=0.3 (C3>0)", 3, 0.3, 0.0, 7, 7, 6},
      {"3D lattice, nu=0.1 (C3<0)", 3, 0.1, 0.0, 7, 6, 6},
      {"3D jittered cloud, nu=0.3", 3, 0.3, 0.25, 7, 6, 6},
      {"3D jittered cloud, nu=0.1", 3, 0.1, 0.25, 6, 6, 6},
      {"3D jittered cloud, triangles and tetrahedra", 3, 0.3, 0.1, 6, 6, 5, true},
      // Upper families of more than 64 points: adjacency rows of two and more words.
      {"2D jittered cloud, m=9.3", 2, 0.4, 0.2, 21, 20, 1, false, 9.3},
      {"3D jittered cloud, m=3.7", 3, 0.3, 0.2, 7, 6, 6, false, 3.7},
  };
  for (const Scene& s : scenes) {
    for (const double failed : {0.0, 0.2}) {
      std::mt19937 rng(12345);
      Body body = ckpd::make_body(
          block(s.dimension, s.nx, s.ny, s.nz, constants_for(s), s.jitter, rng, s.m));
      perturb(body, 0.05, rng);
      fail_bonds(body, failed, rng);
      const std::vector<int> thread_counts{1, 2};
      const std::vector<Difference> diffs = compare_kernels(body, thread_counts);
      for (std::size_t t = 0; t < diffs.size(); ++t) {
        INFO(s.label << ", failed fraction " << failed << ", " << thread_counts[t]
                     << " thread(s): force " << diffs[t].force << ", energy " << diffs[t].energy);
        CHECK(diffs[t].force <= 1e-12);
        CHECK(diffs[t].energy <= 1e-12);
      }
    }
  }
}

TEST_CASE("symmetric kernel equals the reference with points whose bonds have all failed",
          "[symmetric_kernel]") {
  // A point cut loose (every bond failed, as in a punched-out hole) has an empty intact row,
  // which the kernel takes without reading the point's bonds (row_failed's kAllFailed); its
  // neighbours' terms must see every bond to it failed, under either damage rule.
  ThreadCountGuard guard;
  const std::vector<Scene> scenes = {
      {"2D lattice, nu=0.4 (stencil)", 2, 0.4, 0.0, 17, 15, 1},
      {"3D lattice, nu=0.3 (stencil)", 3, 0.3, 0.0, 7, 7, 6},
      {"3D jittered cloud, nu=0.3 (general path)", 3, 0.3, 0.25, 7, 6, 6},
  };
  for (const Scene& s : scenes)
    for (const ckpd::DamageRule rule :
         {ckpd::DamageRule::centre_bonds, ckpd::DamageRule::all_edges}) {
      std::mt19937 rng(97);
      Body body = ckpd::make_body(
          block(s.dimension, s.nx, s.ny, s.nz, constants_for(s), s.jitter, rng, s.m));
      body.damage_rule = rule;
      perturb(body, 0.05, rng);
      fail_bonds(body, 0.05, rng);
      std::bernoulli_distribution cut(0.08);
      std::size_t loose = 0;
      for (std::size_t i = 0; i < body.size(); ++i) {
        if (!cut(rng)) continue;
        ++loose;
        for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k) {
          const std::uint32_t j = body.family.neighbour[k];
          body.bond_intact[k] = 0;
          for (std::size_t q = body.family.offset[j]; q < body.family.offset[j + 1]; ++q)
            if (body.family.neighbour[q] == i) body.bond_intact[q] = 0;
        }
      }
      REQUIRE(loose > 2);
      const std::vector<int> thread_counts{1, 2};
      const std::vector<Difference> diffs = compare_kernels(body, thread_counts);
      for (std::size_t t = 0; t < diffs.size(); ++t) {
        INFO(s.label << ", " << (rule == ckpd::DamageRule::all_edges ? "all_edges" : "centre_bonds")
                     << ", " << loose << " points cut loose, " << thread_counts[t]
                     << " thread(s): force " << diffs[t].force << ", energy " << diffs[t].energy);
        CHECK(diffs[t].force <= 1e-12);
        CHECK(diffs[t].energy <= 1e-12);
      }
    }
}

TEST_CASE("symmetric kernel with damage off ignores nothing and needs no flags",
          "[symmetric_kernel]") {
  ThreadCountGuard guard;
  std::mt19937 rng(7);
  Scene s{"3D lattice", 3, 0.3, 0.0, 6, 6, 6};
  BodyDefinition def = block(3, s.nx, s.ny, s.nz, constants_for(s), 0.0, rng);
  def.critical_stretch = std::numeric_limits<double>::infinity();
  Body body = ckpd::make_body(def);
  REQUIRE_FALSE(body.damage_enabled);
  perturb(body, 0.05, rng);
  const Difference d = compare_kernels(body, 2);
  CHECK(d.force <= 1e-12);
  CHECK(d.energy <= 1e-12);
}

TEST_CASE("symmetric kernel counts agree with the body's N2 and N3", "[symmetric_kernel]") {
  std::mt19937 rng(99);
  for (const Scene& s :
       {Scene{"2D jittered", 2, 0.4, 0.3, 15, 14, 1}, Scene{"3D lattice", 3, 0.3, 0.0, 6, 6, 6},
        Scene{"3D jittered", 3, 0.3, 0.25, 6, 6, 6},
        Scene{"3D both", 3, 0.3, 0.1, 6, 6, 5, true}}) {
    const Body body =
        ckpd::make_body(block(s.dimension, s.nx, s.ny, s.nz, constants_for(s), s.jitter, rng));
    std::vector<std::uint32_t> n2, n3;
    ckpd::count_interactions_symmetric(body, n2, n3);
    INFO(s.label);
    CHECK(n2 == body.n2);
    CHECK(n3 == body.n3);
  }
}

TEST_CASE("symmetric kernel evaluates each tetrahedron once", "[symmetric_kernel]") {
  // On an undamaged lattice every tetrahedron is non-degenerate from all four vertices or from
  // none, so the ordered three-neighbour count is 24 per tetrahedron evaluated.
  std::mt19937 rng(3);
  Scene s{"3D lattice", 3, 0.3, 0.0, 6, 6, 6};
  Body body = ckpd::make_body(block(3, s.nx, s.ny, s.nz, constants_for(s), 0.0, rng));
  perturb(body, 0.05, rng);
  ckpd::SymmetricKernelWorkspace workspace;
  const ckpd::SymmetricKernelStats stats =
      ckpd::compute_internal_force_symmetric(body, false, workspace);
  CHECK(stats.tetrahedra * 24 == body.total_three_neighbour());
  CHECK(stats.bonds == body.bond_count());
  CHECK(stats.triangles == 0);
}

TEST_CASE("symmetric kernel is deterministic for a fixed thread count", "[symmetric_kernel]") {
  ThreadCountGuard guard;
  std::mt19937 rng(5);
  Scene s{"3D jittered", 3, 0.1, 0.25, 6, 6, 5};
  Body body = ckpd::make_body(block(3, s.nx, s.ny, s.nz, constants_for(s), s.jitter, rng));
  perturb(body, 0.05, rng);
  fail_bonds(body, 0.1, rng);
  omp_set_num_threads(2);
  ckpd::compute_internal_force_symmetric(body, true);
  const std::vector<Vec3> force = body.force_density;
  const std::vector<double> energy = body.strain_energy_density;
  for (int repeat = 0; repeat < 3; ++repeat) {
    ckpd::compute_internal_force_symmetric(body, true);
    CHECK(body.force_density == force);
    CHECK(body.strain_energy_density == energy);
  }
}

TEST_CASE("symmetric kernel decides degeneracy per vertex, like the reference",
          "[symmetric_kernel]") {
  ThreadCountGuard guard;
  std::mt19937 rng(11);
  SECTION("a thin triangle: non-degenerate from its middle vertex only") {
    // A = h; thresholds 1e-10 * (product of the vertex's two edges): 2e-10 at the ends
    // (edges 1 and 2), 1e-10 at the middle (edges 1 and 1).
    const double h = 1.5e-10;
    BodyDefinition d;
    d.name = "thin triangle";
    d.dimension = 2;
    d.density = 1;
    d.horizon = 2.5;
    d.constants = {1.0, 1.0, 0.0};
    d.critical_stretch = 10;
    d.reference_position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, h, 0)};
    d.volume.assign(3, 1.0);
    d.full_family_volume = 2;
    Body body = ckpd::make_body(d);
    CHECK(body.n2 == std::vector<std::uint32_t>{0, 2, 0});
    std::vector<std::uint32_t> n2, n3;
    ckpd::count_interactions_symmetric(body, n2, n3);
    CHECK(n2 == body.n2);
    for (Vec3& u : body.displacement) u = Vec3(1e-3 * (rng() % 7), 1e-3 * (rng() % 5), 0);
    const Difference diff = compare_kernels(body, 1);
    CHECK(diff.force <= 1e-12);
    CHECK(diff.energy <= 1e-12);
  }
  SECTION("a flat tetrahedron: non-degenerate from its first vertex only") {
    // |V| = h; thresholds 1e-10 * (product of the vertex's three edges): 2.83e-10 at (0,0,0),
    // 3.16e-10 at (1,0,0) and (0,1,0), 1.41e-9 at (2,2,h).
    const double h = 3e-10;
    BodyDefinition d;
    d.name = "flat tetrahedron";
    d.dimension = 3;
    d.density = 1;
    d.horizon = 3;
    d.constants = {1.0, 0.0, 1.0};
    d.critical_stretch = 10;
    d.reference_position = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(2, 2, h)};
    d.volume.assign(4, 1.0);
    d.full_family_volume = 3;
    Body body = ckpd::make_body(d);
    CHECK(body.n3 == std::vector<std::uint32_t>{6, 0, 0, 0});
    std::vector<std::uint32_t> n2, n3;
    ckpd::count_interactions_symmetric(body, n2, n3);
    CHECK(n3 == body.n3);
    for (Vec3& u : body.displacement)
      u = Vec3(1e-3 * (rng() % 7), 1e-3 * (rng() % 5), 1e-3 * (rng() % 3));
    const Difference diff = compare_kernels(body, 1);
    CHECK(diff.force <= 1e-12);
    CHECK(diff.energy <= 1e-12);
  }
}
