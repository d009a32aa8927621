// The symmetric kernel's batched triangles of planar centres (bodies/symmetric/triangle_batch.hpp,
// issue 21) against the reference kernel: forces and energies to 1e-12 of their largest value on
// perturbed 2D bodies with randomly failed bonds, lattice stencil and general path, lattices and
// jittered clouds, centre_bonds and all_edges, own_family and energy_consistent, with and without
// the inversion penalty, at 1 and 2 OpenMP threads; against the scalar pair loop (the batch
// switched off), the same numbers; the same bits when the kernel runs again; the chunks' pair
// counts leave every remainder modulo the batch width.
#include <omp.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "bodies/body.hpp"
#include "bodies/material.hpp"
#include "bodies/symmetric/triangle_batch.hpp"
#include "bodies/symmetric_kernel.hpp"
#include "kernel_comparison.hpp"
#include "reference/internal_force.hpp"

using namespace kernel_comparison;
using ckpd::DamageRule;
using ckpd::ForceForm;

namespace {

struct Variant {
  ForceForm form;
  DamageRule rule;
  bool stencil;
  double failed;
  double penalty;
  double strain_measure = 0.5;
};

std::string describe(const Scene& s, const Variant& v) {
  return s.label + ", " + ckpd::to_string(v.rule) +
         (v.form == ForceForm::energy_consistent ? ", energy_consistent" : ", own_family") +
         (v.stencil ? ", stencil" : ", general") + ", failed " + std::to_string(v.failed) +
         ", penalty " + std::to_string(v.penalty) + ", m " + std::to_string(v.strain_measure);
}

Body make(const Scene& s, const Variant& v, std::mt19937& rng) {
  BodyDefinition d = block(s.dimension, s.nx, s.ny, s.nz, constants_for(s), s.jitter, rng, s.m);
  if (v.form == ForceForm::energy_consistent) vary_volumes(d, rng);
  d.force_form = v.form;
  d.damage_rule = v.rule;
  d.lattice_stencil = v.stencil;
  d.inversion_penalty = v.penalty;
  d.strain_measure = v.strain_measure;
  Body body = ckpd::make_body(d);
  REQUIRE(ckpd::uses_lattice_stencil(body) == (v.stencil && s.jitter == 0));
  // Large enough with the penalty that many triangles turn over.
  perturb(body, v.penalty > 0 ? 0.6 : 0.05, rng);
  fail_bonds(body, v.failed, rng);
  return body;
}

const std::vector<Scene>& scenes() {
  static const std::vector<Scene> s = {
      {"2D lattice nu=0.4 (C2>0)", 2, 0.4, 0.0, 17, 15, 1},
      {"2D lattice nu=0.2 (C2<0)", 2, 0.2, 0.0, 16, 13, 1},
      {"2D jittered cloud nu=0.4", 2, 0.4, 0.3, 17, 15, 1},
      // Upper families of more than 64 slots (rows of two and more words) and more pairs than
      // a chunk holds.
      {"2D lattice m=9.3", 2, 0.4, 0.0, 24, 22, 1, false, 9.3},
      {"2D jittered cloud m=9.3", 2, 0.4, 0.2, 21, 20, 1, false, 9.3},
  };
  return s;
}

std::vector<Variant> variants() {
  std::vector<Variant> v;
  for (const ForceForm form : {ForceForm::own_family, ForceForm::energy_consistent})
    for (const bool stencil : {true, false}) {
      v.push_back({form, DamageRule::centre_bonds, stencil, 0.0, 0.0});
      v.push_back({form, DamageRule::centre_bonds, stencil, 0.2, 0.0});
      v.push_back({form, DamageRule::all_edges, stencil, 0.2, 0.0});
      v.push_back({form, DamageRule::centre_bonds, stencil, 0.1, 1.0});
      v.push_back({form, DamageRule::all_edges, stencil, 0.1, 1.0});
    }
  return v;
}

// m = 3.015 (the large families, m = 9.3, cost most of the tests' time).
bool small_family(const Scene& s) {
  return s.m == kM;
}

// Restores the batch switch when a test ends.
struct BatchSwitchGuard {
  ~BatchSwitchGuard() { ckpd::symmetric::batched_triangles_enabled = true; }
};

}  // namespace

TEST_CASE("batched triangles equal the reference kernel in every force form and damage rule",
          "[batched_triangles]") {
  ThreadCountGuard guard;
  const std::vector<Variant> all = variants();
  for (const Scene& s : scenes())
    for (std::size_t n = 0; n < all.size(); ++n) {
      const Variant& v = all[n];
      if (v.stencil && s.jitter > 0) continue;       // clouds have no stencil
      if (!small_family(s) && n % 4 != 0) continue;  // test time: every fourth variant
      std::mt19937 rng(4711);
      Body body = make(s, v, rng);
      const std::vector<int> threads{1, 2};
      const std::vector<Difference> diffs = compare_kernels(body, threads);
      for (std::size_t t = 0; t < diffs.size(); ++t) {
        INFO(describe(s, v) << ", " << threads[t] << " thread(s): force " << diffs[t].force
                            << ", energy " << diffs[t].energy);
        CHECK(diffs[t].force <= 1e-12);
        CHECK(diffs[t].energy <= 1e-12);
      }
    }
}

TEST_CASE("batched triangles give the scalar pair loop's numbers and the same bits again",
          "[batched_triangles]") {
  // The batch computes every vertex's share with the scalar loop's operations and adds them in
  // its order: the same doubles (== ignores the sign of a zero, the only difference allowed).
  ThreadCountGuard guard;
  BatchSwitchGuard restore;
  std::size_t batched = 0;
  unsigned residues = 0;
  const std::vector<Variant> all = variants();
  for (const double m : {0.5, -0.5})  // the linear law (vector lanes) and a Seth-Hill measure
    for (const Scene& s : scenes())
      for (std::size_t n = 0; n < all.size(); ++n) {
        const Variant& base = all[n];
        if (base.stencil && s.jitter > 0) continue;
        // Test time: the large families with every fourth variant and the linear law only.
        if (!small_family(s) && (n % 4 != 0 || m != 0.5)) continue;
        Variant v = base;
        v.strain_measure = m;
        std::mt19937 rng(99);
        Body body = make(s, v, rng);
        for (const int threads : {1, 2}) {
          INFO(describe(s, v) << ", " << threads << " thread(s)");
          omp_set_num_threads(threads);
          ckpd::SymmetricKernelWorkspace workspace;
          ckpd::symmetric::batched_triangles_enabled = false;
          const ckpd::SymmetricKernelStats scalar_stats =
              ckpd::compute_internal_force_symmetric(body, true, workspace);
          const std::vector<Vec3> force = body.force_density;
          const std::vector<double> energy = body.strain_energy_density;
          for (int t = 0; t < threads; ++t)
            CHECK(workspace.thread(static_cast<std::size_t>(t)).tri_centres == 0);
          ckpd::symmetric::batched_triangles_enabled = true;
          for (int repeat = 0; repeat < 2; ++repeat) {
            const ckpd::SymmetricKernelStats stats =
                ckpd::compute_internal_force_symmetric(body, true, workspace);
            CHECK(body.force_density == force);
            CHECK(body.strain_energy_density == energy);
            CHECK(stats.triangles == scalar_stats.triangles);
            CHECK(stats.triangles_per_vertex == scalar_stats.triangles_per_vertex);
            CHECK(stats.inverted_triangles == scalar_stats.inverted_triangles);
          }
          for (int t = 0; t < threads; ++t) {
            const auto& th = workspace.thread(static_cast<std::size_t>(t));
            batched += th.tri_centres;
            residues |= th.tri_residues;
          }
        }
      }
  CHECK(batched > 0);
  // Chunks of every size modulo 8 (so modulo the batch width 4 or 8).
  CHECK(residues == 0xffu);
}

TEST_CASE("batched triangles leave centres with out-of-plane offsets to the pair loop",
          "[batched_triangles]") {
  // A 2D body some of whose points have moved out of the plane (z displacement): centres with
  // such a point in their upper family have triangles whose area vectors are not along z, and
  // take the pair loop; the others are batched. Both equal the reference.
  ThreadCountGuard guard;
  omp_set_num_threads(1);
  for (const bool stencil : {true, false}) {
    INFO((stencil ? "stencil" : "general"));
    std::mt19937 rng(5);
    const Scene s{"2D lattice nu=0.4", 2, 0.4, 0.0, 17, 15, 1};
    const Variant v{ForceForm::own_family, DamageRule::centre_bonds, stencil, 0.1, 0.0};
    Body body = make(s, v, rng);
    for (std::size_t i = 0; i < body.size(); i += 97) body.displacement[i].z() = 2e-5;
    ckpd::SymmetricKernelWorkspace workspace;
    ckpd::compute_internal_force_symmetric(body, true, workspace);
    const std::size_t batched = workspace.thread(0).tri_centres;
    CHECK(batched > body.size() / 2);
    CHECK(batched + body.size() / 20 < body.size());
    const Difference d = compare_kernels(body, 1);
    CHECK(d.force <= 1e-12);
    CHECK(d.energy <= 1e-12);
  }
}
