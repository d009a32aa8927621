#include "bodies/symmetric_kernel.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "bodies/ckpd_model.hpp"
#include "bodies/damage.hpp"
#include "bodies/symmetric/load_general.hpp"

namespace ckpd {

SymmetricKernelWorkspace::SymmetricKernelWorkspace() = default;
SymmetricKernelWorkspace::~SymmetricKernelWorkspace() = default;

void SymmetricKernelWorkspace::ensure_threads(std::size_t count) {
  while (threads_.size() < count) threads_.push_back(std::make_unique<SymmetricKernelThread>());
}

namespace symmetric {

ContextBase make_context_base(const Body& body) {
  ContextBase ctx;
  ctx.body = &body;
  ctx.X = body.reference_position.data();
  ctx.u = body.displacement.empty() ? nullptr : body.displacement.data();
  ctx.offset = body.family.offset.data();
  ctx.neighbour = body.family.neighbour.data();
  ctx.intact = body.damage_enabled ? body.bond_intact.data() : nullptr;
  ctx.all_edges = ctx.intact != nullptr && body.damage_rule == DamageRule::all_edges;
  ctx.pairs = body.has_pairs();
  ctx.triples = body.has_triples();
  ctx.degenerate = body.degenerate_fraction;
  const SetScreens& s = body.screens;
  ctx.hi2 = s.hi2;
  ctx.lo2 = s.lo2;
  ctx.hi3 = s.hi3;
  ctx.lo3 = s.lo3;
  ctx.well2 = s.well2;
  ctx.well3 = s.well3;
  return ctx;
}

}  // namespace symmetric

SetScreens set_screens(const Body& body) {
  using namespace symmetric;
  double min_length2 = std::numeric_limits<double>::infinity();
  const std::size_t n = body.size();
#pragma omp parallel for schedule(static) reduction(min : min_length2)
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k)
      min_length2 = std::min(min_length2, (body.reference_position[body.family.neighbour[k]] -
                                           body.reference_position[i])
                                              .squaredNorm());
  // From the largest possible edge (the horizon) and the shortest bond in the body.
  const double min_bond_length = std::sqrt(min_length2);
  const double D = body.horizon * (1 + kHorizonTolerance);
  const double D2 = D * D, D3 = D2 * D;
  const double L2 = min_bond_length * min_bond_length, L3 = L2 * min_bond_length;
  const double f = body.degenerate_fraction;
  SetScreens s;
  s.hi2 = f * (1 + kThresholdSlack) * D2 + kRoundoff * D2;
  s.hi3 = f * (1 + kThresholdSlack) * D3 + kRoundoff * D3;
  s.lo2 = f * (1 - kThresholdSlack) * L2 - kRoundoff * D2;
  s.lo3 = f * (1 - kThresholdSlack) * L3 - kRoundoff * D3;
  s.well2 = std::max(s.hi2, kWellConditioned2 * D2);
  s.well3 = std::max(s.hi3, kWellConditioned3 * D3);
  return s;
}

bool uses_lattice_stencil(const Body& body) {
  // The stencil serves only the interaction families it was built with (the constants set
  // which; they do not change sign after the body is made, but a caller may zero one). Bond-only
  // bodies keep the general path: the slot look-up costs more than the 1/L it saves (measured
  // 0.87x on a 24^3 block, nu = 0.25; docs/PERFORMANCE.md).
  const LatticeStencil* st = body.stencil.get();
  const bool pairs = body.has_pairs(), triples = body.has_triples();
  return st != nullptr && (pairs || triples) && (!pairs || !st->inv_area.empty()) &&
         (!triples || !st->triple_row.empty()) && !st->adjacency.empty();
}

SymmetricKernelStats compute_internal_force_symmetric(Body& body, bool with_energy,
                                                      SymmetricKernelWorkspace& workspace) {
  return force_model(body).symmetric(body, with_energy, workspace);
}

namespace {
// One workspace per calling thread: two host threads may evaluate two bodies at once.
SymmetricKernelWorkspace& host_workspace() {
  thread_local SymmetricKernelWorkspace workspace;
  return workspace;
}
}  // namespace

SymmetricKernelStats compute_internal_force_symmetric(Body& body, bool with_energy) {
  return compute_internal_force_symmetric(body, with_energy, host_workspace());
}

SymmetricKernelStats fail_bonds_and_compute_internal_force(Body& body, bool with_energy,
                                                           double half_drift,
                                                           FailureUpdate& failure) {
  const ForceModelKernels& model = force_model(body);
  if (model.fail_and_symmetric != nullptr)
    return model.fail_and_symmetric(body, with_energy, half_drift, host_workspace(), failure);
  failure = fail_overstretched_bonds(body, half_drift);
  return model.symmetric(body, with_energy, host_workspace());
}

void count_interactions_symmetric(const Body& body, std::vector<std::uint32_t>& n2,
                                  std::vector<std::uint32_t>& n3) {
  const std::size_t n = body.size();
  n2.assign(n, 0);
  n3.assign(n, 0);
  // The counts are the sets' geometry: any model's context enumerates the same sets.
  symmetric::Context<CkpdModel> ctx;
  static_cast<symmetric::ContextBase&>(ctx) = symmetric::make_context_base(body);
  ctx.model = CkpdModel::of(body);
  ctx.intact = nullptr;  // counts include failed bonds, like body.n2 / body.n3
  if (!(ctx.pairs || ctx.triples)) return;
  SymmetricKernelThread t;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t m = symmetric::load_upper_family(ctx, i, t, true);
    const std::size_t W = t.words;
    const auto ii = static_cast<std::uint32_t>(i);
    for (std::size_t a = 0; a + 1 < m; ++a) {
      const std::uint64_t* ra = &t.adj[a * W];
      for (std::size_t b = a + 1; b < m; ++b) {
        if (!symmetric::bit(ra, b)) continue;
        const std::uint32_t vj = t.up[a], vk = t.up[b];
        const Vec3 P(t.Rx[a], t.Ry[a], t.Rz[a]), Q(t.Rx[b], t.Ry[b], t.Rz[b]);
        const Vec3 PQ = P.cross(Q);
        if (ctx.pairs) {
          const unsigned mask = symmetric::triangle_mask(ctx, PQ.norm(), ii, vj, vk);
          n2[i] += 2 * (mask & 1);
          n2[vj] += 2 * ((mask >> 1) & 1);
          n2[vk] += 2 * ((mask >> 2) & 1);
        }
        if (!ctx.triples) continue;
        const std::uint64_t* rb = &t.adj[b * W];
        for (std::size_t c = b + 1; c < m; ++c) {
          if (!symmetric::bit(ra, c) || !symmetric::bit(rb, c)) continue;
          const Vec3 R(t.Rx[c], t.Ry[c], t.Rz[c]);
          const unsigned mask =
              symmetric::tetrahedron_mask(ctx, std::abs(PQ.dot(R)), ii, vj, vk, t.up[c]);
          n3[i] += 6 * (mask & 1);
          n3[vj] += 6 * ((mask >> 1) & 1);
          n3[vk] += 6 * ((mask >> 2) & 1);
          n3[t.up[c]] += 6 * ((mask >> 3) & 1);
        }
      }
    }
  }
}

}  // namespace ckpd
