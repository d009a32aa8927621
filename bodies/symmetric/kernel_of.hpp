#pragma once
// compute_internal_force_symmetric for one force model (instantiated in the model's table,
// force_model_kernels.hpp).
#include <omp.h>

#include <algorithm>

#include "bodies/bond_failure.hpp"
#include "bodies/symmetric/bond_only.hpp"
#include "bodies/symmetric/process_point.hpp"

namespace ckpd::symmetric {

// With `failure` (not null), the damage step first: *failure = fail_overstretched_bonds_of(
// model, body, half_drift), then the forces of the bonds that survive it. A bond-only body
// (bond_only_path) does both in one pass over its bonds; any other body calls the two in turn.
template <class Model>
SymmetricKernelStats compute_of(Body& body, bool with_energy, SymmetricKernelWorkspace& workspace,
                                double half_drift = 0, FailureUpdate* failure = nullptr) {
  const std::size_t n = body.size();
  Context<Model> ctx;
  static_cast<ContextBase&>(ctx) = make_context_base(body);
  ctx.model = Model::of(body);
  ctx.exact = workspace.exact_point;
  workspace.ensure_threads(static_cast<std::size_t>(std::max(1, omp_get_max_threads())));
  const bool bonds_only = bond_only_path(ctx, workspace);
  // The fused damage step needs damage on (otherwise nothing fails: the plain kernel).
  const bool fuse = failure != nullptr && bonds_only && body.damage_enabled;
  if (failure != nullptr) *failure = {};
  if (failure != nullptr && !fuse) {
    *failure = fail_overstretched_bonds_of(ctx.model, body, half_drift);
    // The flags may have changed.
    static_cast<ContextBase&>(ctx) = make_context_base(body);
    ctx.exact = workspace.exact_point;
  }
  FusedFailure fused;
  if (fuse) {
    fused.protect = !body.no_failure.empty();
    // All zero between calls: grown (and zeroed) only for a larger body than any before.
    if (workspace.failing.size() < body.family.neighbour.size())
      workspace.failing.resize(body.family.neighbour.size(), 0);
    if (workspace.touched.size() < n) workspace.touched.resize(n, 0);
    fused.failing = workspace.failing.data();
    fused.touched = workspace.touched.data();
  }
  if (uses_lattice_stencil(body))
    ctx.stencil = body.stencil.get();
  else if (body.upper_rows != nullptr && body.upper_rows->matches(body.family))
    ctx.upper_rows = body.upper_rows.get();
  // Per point, whether a bond of its row has failed: a centre with none in its own row and its
  // upper neighbours' has an intact family (its rows need no intact copy, and its tetrahedra
  // go to the groups alone: intact_pair_loop).
  if (ctx.intact != nullptr && !bonds_only) {
    if (workspace.row_failed.size() < n) workspace.row_failed.resize(n);
    if (workspace.row_upper.size() < n) workspace.row_upper.resize(n);
    ctx.row_failed = workspace.row_failed.data();
    ctx.row_upper = workspace.row_upper.data();
    if (ctx.stencil != nullptr) {
      const std::size_t words = n * ctx.stencil->words;
      if (workspace.failed_upper.size() < words) workspace.failed_upper.resize(words);
      ctx.failed_upper = workspace.failed_upper.data();
    }
  }
  int team = 1;
  // Static schedule: which thread handles which point is a function of the thread count only,
  // so each thread's partial sums, and their sum in thread order, are reproducible. Chunks of 64
  // interleave the threads finely enough to spread the cheap points (few upper neighbours: the
  // high-index surface); measured on a 20^3 block with 2 threads: chunks of 16 scaled 1.85x,
  // 64 to 256 1.95x (consecutive points write to overlapping neighbours: better locality).
  constexpr int kChunk = 64;
#pragma omp parallel
  {
    const std::size_t t = static_cast<std::size_t>(omp_get_thread_num());
#pragma omp single
    team = omp_get_num_threads();
    SymmetricKernelThread& th = workspace.thread(t);
    th.stats = {};
    th.full_pairs.stencil = nullptr;  // the body's stencil may be another than last time's
    th.failed = 0;
    th.force.assign(n, Vec3::Zero());  // keeps its capacity: no allocation after the first call
    // The energy buffer grows with the force buffer, not at the first evaluation with energy:
    // a host thread may meet a larger body first in a step without energy (small bodies are
    // dealt to threads dynamically), and the energy step would then allocate.
    if (th.energy.capacity() < n) th.energy.reserve(n);
    if (with_energy) th.energy.assign(n, 0.0);
    if (ctx.row_failed != nullptr) {
#pragma omp for schedule(static)
      for (std::size_t i = 0; i < n; ++i) {
        const std::size_t begin = body.family.offset[i], end = body.family.offset[i + 1];
        std::size_t failed = 0;
        for (std::size_t k = begin; k < end; ++k) failed += ctx.intact[k] == 0;
        workspace.row_failed[i] = failed == 0             ? 0
                                  : failed == end - begin ? ContextBase::kAllFailed
                                                          : ContextBase::kSomeFailed;
        if (failed == 0 || failed == end - begin) continue;
        const std::size_t upper =
            static_cast<std::size_t>(std::upper_bound(ctx.neighbour + begin, ctx.neighbour + end,
                                                      static_cast<std::uint32_t>(i)) -
                                     ctx.neighbour);
        workspace.row_upper[i] = upper;
        // The stencil path's failed upper bonds in i's own slots, once per row and step: every
        // centre with i among its upper neighbours reads them (load_stencil.hpp), where each
        // scanned i's flags for itself.
        if (ctx.failed_upper != nullptr) {
          const LatticeStencil& st = *ctx.stencil;
          std::uint64_t* row = workspace.failed_upper.data() + i * st.words;
          std::fill_n(row, st.words, 0);
          for_each_flag_other_than(ctx.intact, upper, end, 1, [&](std::size_t k) {
            const std::size_t s = static_cast<std::size_t>(st.slot(i, ctx.neighbour[k]));
            row[s >> 6] |= std::uint64_t{1} << (s & 63);
          });
        }
      }
    }
    const bool penalty = ctx.model.has_penalty();
    // Body::owned_centres (MPI ranks): only this rank's centres; empty: all of them.
    const std::uint8_t* owned = body.owned_centres.empty() ? nullptr : body.owned_centres.data();
    const std::uint8_t* skip = workspace.skip_centre;  // the far field's linear centres
    auto all_points = [&]<bool kEnergy, bool kPenalty>() {
      if (bonds_only) {
        std::size_t failed = 0, ghost_failed = 0;
        if (fuse) {
#pragma omp for schedule(static, kChunk)
          for (std::size_t i = 0; i < n; ++i)
            if (owned == nullptr || owned[i] != 0)
              bond_only_point<Model, kEnergy, true>(ctx, i, th, fused, failed);
            else
              ghost_bond_failures<Model>(ctx, i, fused, ghost_failed);
        } else {
#pragma omp for schedule(static, kChunk)
          for (std::size_t i = 0; i < n; ++i)
            if (owned == nullptr || owned[i] != 0)
              bond_only_point<Model, kEnergy, false>(ctx, i, th, fused, failed);
        }
        th.failed = failed;
        th.ghost_failed = ghost_failed;
      } else if (ctx.stencil != nullptr) {
#pragma omp for schedule(static, kChunk)
        for (std::size_t i = 0; i < n; ++i)
          if ((owned == nullptr || owned[i] != 0) && (skip == nullptr || !skip[i]))
            process_point<Model, kEnergy, kPenalty, true>(ctx, i, th);
      } else {
#pragma omp for schedule(static, kChunk)
        for (std::size_t i = 0; i < n; ++i)
          if ((owned == nullptr || owned[i] != 0) && (skip == nullptr || !skip[i]))
            process_point<Model, kEnergy, kPenalty, false>(ctx, i, th);
      }
    };
    if (with_energy && penalty) {
      all_points.template operator()<true, true>();
    } else if (with_energy) {
      all_points.template operator()<true, false>();
    } else if (penalty) {
      all_points.template operator()<false, true>();
    } else {
      all_points.template operator()<false, false>();
    }
    // Fixed-order reduction: thread 0, 1, ... for every point.
#pragma omp for schedule(static)
    for (std::size_t p = 0; p < n; ++p) {
      Vec3 f = workspace.thread(0).force[p];
      for (int s = 1; s < team; ++s) f += workspace.thread(static_cast<std::size_t>(s)).force[p];
      body.force_density[p] = f;
      if (with_energy) {
        double e = workspace.thread(0).energy[p];
        for (int s = 1; s < team; ++s) e += workspace.thread(static_cast<std::size_t>(s)).energy[p];
        body.strain_energy_density[p] = e;
      }
    }
  }
  SymmetricKernelStats stats;
  for (int s = 0; s < team; ++s) {
    const SymmetricKernelStats& x = workspace.thread(static_cast<std::size_t>(s)).stats;
    stats.bonds += x.bonds;
    stats.triangles += x.triangles;
    stats.tetrahedra += x.tetrahedra;
    stats.triangles_per_vertex += x.triangles_per_vertex;
    stats.tetrahedra_per_vertex += x.tetrahedra_per_vertex;
    stats.inverted_triangles += x.inverted_triangles;
    stats.inverted_tetrahedra += x.inverted_tetrahedra;
  }
  if (fuse) {
    std::size_t ghost_failed = 0;
    for (int s = 0; s < team; ++s) {
      failure->failed += workspace.thread(static_cast<std::size_t>(s)).failed;
      ghost_failed += workspace.thread(static_cast<std::size_t>(s)).ghost_failed;
    }
    if (failure->failed > 0 || ghost_failed > 0)
      failure->dissipated = book_fused_failures(ctx.model, body, half_drift, fused);
  }
  return stats;
}

}  // namespace ckpd::symmetric
