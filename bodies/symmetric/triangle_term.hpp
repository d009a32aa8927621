#pragma once
// The triangle {i, a, b} of one pair: evaluated once with shared geometry and given to each of
// its active vertices, or, ill-conditioned or near the degeneracy threshold (general path
// only), vertex by vertex as the reference does.
#include "bodies/symmetric/pair.hpp"
#include "bodies/symmetric/per_vertex_terms.hpp"

namespace ckpd::symmetric {

// An ill-conditioned triangle {i, a, b} (or one near the degeneracy threshold), own-family
// form: each of its active vertices (bit 0 i, 1 a, 2 b of `active`) on its own, as the reference.
template <class Model, bool kEnergy>
inline void triangle_separate(const Context<Model>& ctx, SymmetricKernelThread& t, Centre& centre,
                              std::size_t a, std::size_t b, unsigned active) {
  const std::uint32_t ii = centre.index, vj = t.up[a], vk = t.up[b];
  Vec3 f;
  double w = 0;
  bool seen = false, inverted = false, inv = false;
  if ((active & 1) && reference_triangle_term(ctx, ii, vj, vk, f, w, inv)) {
    centre.add<kEnergy>(t, 0, true, f, w);
    seen = true;
    inverted |= inv;
  }
  if ((active & 2) && reference_triangle_term(ctx, vj, ii, vk, f, w, inv)) {
    centre.add<kEnergy>(t, a, false, f, w);
    seen = true;
    inverted |= inv;
  }
  if ((active & 4) && reference_triangle_term(ctx, vk, ii, vj, f, w, inv)) {
    centre.add<kEnergy>(t, b, false, f, w);
    seen = true;
    inverted |= inv;
  }
  if constexpr (kEnergy) centre.count.inverted_triangles += inverted;
  centre.count.triangles += seen;
  centre.count.triangles_per_vertex += seen;
}

template <class Model, bool kEnergy, bool kPenalty, bool kStencil>
inline void triangle_term(const Context<Model>& ctx, SymmetricKernelThread& t, Centre& centre,
                          const Pair& pr) {
  if (!(pr.act_i || pr.act_j || pr.act_k)) return;
  const LatticeStencil* st = ctx.stencil;
  const std::size_t a = pr.a, b = pr.b;
  const double* pa = pr.pa;
  const double* pb = pr.pb;
  const double* pq = pr.pq;
  double* __restrict fx = t.fx.data();
  double* __restrict fy = t.fy.data();
  double* __restrict fz = t.fz.data();
  double* __restrict slot_w = t.w.data();
  const double* __restrict k2 = t.k2.data();
  const double* __restrict e2 = t.e2.data();
  const Body& body = *ctx.body;
  // Stencil: 1/A from the table, 0 for a degenerate (collinear) pair, and a lattice's sets are
  // never ill-conditioned. General: A from the reference offsets.
  double A = 0, inv_A = 0, ref_z = 0;
  if constexpr (kStencil) {
    inv_A = st->inv_area[pr.number];
    ref_z = st->area_z[pr.number];
  } else {
    A = std::sqrt(pr.RPQ[0] * pr.RPQ[0] + pr.RPQ[1] * pr.RPQ[1] + pr.RPQ[2] * pr.RPQ[2]);
    ref_z = pr.RPQ[2];
  }
  const unsigned active = unsigned(pr.act_i) | unsigned(pr.act_j) << 1 | unsigned(pr.act_k) << 2;
  if (kStencil ? inv_A != 0 : A > ctx.well2) {
    const double an = std::sqrt(pq[0] * pq[0] + pq[1] * pq[1] + pq[2] * pq[2]);
    const bool inverted = (kEnergy || kPenalty) && ctx.model.triangle_inverted(pq[2], ref_z);
    if constexpr (kEnergy) centre.count.inverted_triangles += inverted;
    double fa, en;
    if constexpr (kStencil) {
      const InverseMeasure M{inv_A};
      fa = ctx.model.template triangle_coefficient<kPenalty>(M, an, inverted);
      en = ctx.model.template triangle_energy_measure<kPenalty>(M, an, inverted);
    } else {
      const ReferenceMeasure M{A};
      fa = ctx.model.template triangle_coefficient<kPenalty>(M, an, inverted);
      en = ctx.model.template triangle_energy_measure<kPenalty>(M, an, inverted);
    }
    double g[3];
    for (int d = 0; d < 3; ++d) g[d] = fa * pq[d];
    // d|a|/dx^c = G_c x n with G_i = p - q, G_j = q, G_k = -p, and
    // -2 C2 dV2 (|a|/A - 1) G_c x n = -2 C2 dV2 G_c x g.
    if (active & 1) {
      const double k2i = ctx.model.triangle_force_weight(body.dv2[centre.index]);
      const double qp[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
      centre.fx += k2i * (qp[1] * g[2] - qp[2] * g[1]);
      centre.fy += k2i * (qp[2] * g[0] - qp[0] * g[2]);
      centre.fz += k2i * (qp[0] * g[1] - qp[1] * g[0]);
      if constexpr (kEnergy)
        centre.w += ctx.model.triangle_energy_weight(body.dv2[centre.index]) * en;
    }
    if (active & 2) {
      fx[a] -= k2[a] * (pb[1] * g[2] - pb[2] * g[1]);
      fy[a] -= k2[a] * (pb[2] * g[0] - pb[0] * g[2]);
      fz[a] -= k2[a] * (pb[0] * g[1] - pb[1] * g[0]);
      if constexpr (kEnergy) slot_w[a] += e2[a] * en;
    }
    if (active & 4) {
      fx[b] += k2[b] * (pa[1] * g[2] - pa[2] * g[1]);
      fy[b] += k2[b] * (pa[2] * g[0] - pa[0] * g[2]);
      fz[b] += k2[b] * (pa[0] * g[1] - pa[1] * g[0]);
      if constexpr (kEnergy) slot_w[b] += e2[b] * en;
    }
    ++centre.count.triangles;
  } else if (!kStencil && A >= ctx.lo2) {
    // Ill-conditioned or near the degeneracy threshold: each vertex on its own.
    triangle_separate<Model, kEnergy>(ctx, t, centre, a, b, active);
  }
}

}  // namespace ckpd::symmetric
