#pragma once
// Tetrahedra {i, a, b, c} of one pair (a, b): c > b bonded to both a and b (and to i: every
// slot is). With p, q, r the current offsets to a, b, c and v = p.(q x r), the gradients are
// g_j = q x r, g_k = r x p, g_l = p x q, g_i = -(g_j + g_k + g_l), and each vertex gets
// -6 C3 dV3 f g with f the model's coefficient (v/|V| - sign v). Summed over c at fixed (a, b),
// the forces on i, j, k need only S = sum f r and F = sum f (the cross products are linear), so
// the per-tetrahedron work is two dot products, one division and the fourth vertex's force.
// Sums with all four vertices active go to (S, F, E); sums for partially active sets to
// per-vertex accumulators.
#include "bodies/symmetric/pair.hpp"
#include "bodies/symmetric/per_vertex_terms.hpp"
#include "bodies/symmetric/tetrahedron_group.hpp"

namespace ckpd::symmetric {

// An ill-conditioned tetrahedron {i, a, b, c} (or one near the degeneracy threshold): each
// active vertex decides and evaluates its own term as the reference does.
template <class Model, bool kEnergy>
inline void separate_tetrahedron(const Context<Model>& ctx, SymmetricKernelThread& t,
                                 Centre& centre, std::size_t a, std::size_t b, std::size_t c,
                                 unsigned active) {
  const std::uint32_t* up = t.up.data();
  const std::uint32_t ii = centre.index, vj = up[a], vk = up[b], vl = up[c];
  Vec3 f;
  double w = 0;
  bool seen = false, inverted = false, inv = false;
  if ((active & 1) && reference_tetrahedron_term(ctx, ii, vj, vk, vl, f, w, inv)) {
    centre.add<kEnergy>(t, 0, true, f, w);
    seen = true;
    inverted |= inv;
  }
  if ((active & 2) && reference_tetrahedron_term(ctx, vj, ii, vk, vl, f, w, inv)) {
    centre.add<kEnergy>(t, a, false, f, w);
    seen = true;
    inverted |= inv;
  }
  if ((active & 4) && reference_tetrahedron_term(ctx, vk, ii, vj, vl, f, w, inv)) {
    centre.add<kEnergy>(t, b, false, f, w);
    seen = true;
    inverted |= inv;
  }
  if ((active & 8) && reference_tetrahedron_term(ctx, vl, ii, vj, vk, f, w, inv)) {
    centre.add<kEnergy>(t, c, false, f, w);
    seen = true;
    inverted |= inv;
  }
  if constexpr (kEnergy) centre.count.inverted_tetrahedra += inverted;
  centre.count.tetrahedra += seen;
  centre.count.tetrahedra_per_vertex += seen;
}

template <class Model, bool kEnergy, bool kPenalty, bool kStencil>
CKPD_TETRAHEDRON_LOOP_INLINE inline void tetrahedron_loop(
    const Context<Model>& ctx, SymmetricKernelThread& t, Centre& centre, Pair& pr,
    [[maybe_unused]] batch::PairGroup& group) {
  const Model& model = ctx.model;
  const Body& body = *ctx.body;
  const LatticeStencil* st = ctx.stencil;
  const std::size_t W = t.words, a = pr.a, b = pr.b;
  const std::uint64_t* own = t.own.data();
  const std::uint64_t* present = t.present.data();
  const double* __restrict Rx = t.Rx.data();
  const double* __restrict Ry = t.Ry.data();
  const double* __restrict Rz = t.Rz.data();
  const double* __restrict rx = t.rx.data();
  const double* __restrict ry = t.ry.data();
  const double* __restrict rz = t.rz.data();
  const double* __restrict k3 = t.k3.data();
  const double* __restrict e3 = t.e3.data();
  double* __restrict fx = t.fx.data();
  double* __restrict fy = t.fy.data();
  double* __restrict fz = t.fz.data();
  double* __restrict slot_w = t.w.data();
  const double* pa = pr.pa;
  const double* pb = pr.pb;
  const double* pq = pr.pq;
  const double* RPQ = pr.RPQ;
  const std::uint64_t* ra = pr.ra;
  const std::uint64_t* ia = pr.ia;
  const std::uint64_t* rb = &t.adj[b * W];
  const std::uint64_t* ib = t.intact_is_adjacency ? rb : &t.adj_intact[b * W];
  double S[3] = {0, 0, 0}, F = 0, E = 0;
  double Si[3] = {0, 0, 0}, Fi = 0, Ei = 0;
  // j and k need no F: their gradients q x r and r x p are linear in r alone.
  double Sj[3] = {0, 0, 0}, Ej = 0;
  double Sk[3] = {0, 0, 0}, Ek = 0;
  bool any = false;
  std::uint64_t n_tetrahedra = 0, n_inverted = 0;
  // A well-conditioned tetrahedron with some vertices inactive: vertex by vertex.
  auto partial = [&](std::size_t c, unsigned mask, double signed_V) {
    const ReferenceMeasure V{std::abs(signed_V)};
    const double r[3] = {rx[c], ry[c], rz[c]};
    const double v = pq[0] * r[0] + pq[1] * r[1] + pq[2] * r[2];
    const bool inverted = (kEnergy || kPenalty) && model.tetrahedron_inverted(v, signed_V);
    if constexpr (kEnergy) n_inverted += inverted;
    const double f = model.template tetrahedron_coefficient<kPenalty>(V, v, inverted);
    double en = 0;
    if constexpr (kEnergy) {
      en = model.tetrahedron_energy_measure(V, v);
      if (kPenalty && inverted) en += model.tetrahedron_penalty_measure(v);
    }
    if (mask & 1) {
      for (int d = 0; d < 3; ++d) Si[d] += f * r[d];
      Fi += f;
      Ei += en;
    }
    if (mask & 2) {
      for (int d = 0; d < 3; ++d) Sj[d] += f * r[d];
      Ej += en;
    }
    if (mask & 4) {
      for (int d = 0; d < 3; ++d) Sk[d] += f * r[d];
      Ek += en;
    }
    if (mask & 8) {
      const double kl = k3[c] * f;
      fx[c] -= kl * pq[0];
      fy[c] -= kl * pq[1];
      fz[c] -= kl * pq[2];
      if constexpr (kEnergy) slot_w[c] += e3[c] * en;
    }
    any = true;
    ++n_tetrahedra;
  };
  auto separate = [&](std::size_t c, unsigned active) {
    separate_tetrahedron<Model, kEnergy>(ctx, t, centre, a, b, c, active);
  };
  // Stencil path: the pair's row of non-degenerate triples; triple (a, b, c) is number
  // triple_base[pair] + the rank of c in that row, and its entry is 1 / V.
  const std::uint64_t* triple_row = kStencil ? &st->triple_row[pr.number * W] : nullptr;
  std::size_t triple_rank = kStencil ? st->triple_base[pr.number] : 0;

  for (std::size_t wc = b >> 6; wc < W; ++wc) {
    std::uint64_t cand;
    std::size_t word_triple = 0;
    if constexpr (kStencil) {
      const std::uint64_t tr = triple_row[wc];
      cand = tr & present[wc];
      word_triple = triple_rank;
      triple_rank += static_cast<std::size_t>(std::popcount(tr));
    } else {
      cand = ra[wc] & rb[wc];
    }
    if (pr.only != nullptr) cand &= pr.only[wc];
    if (!cand) continue;
    // 1 / V of triple c, whose bit is in word wc (stencil path only).
    auto inv_volume = [&](std::size_t c) {
      return st
          ->inv_volume[word_triple + static_cast<std::size_t>(std::popcount(
                                         triple_row[wc] & ((std::uint64_t{1} << (c & 63)) - 1)))];
    };
    // Per vertex, the c whose tetrahedron it sees with its three bonds intact. Under all_edges
    // all six edges must be intact (i's three, a-b, a-c, b-c), for every vertex.
    const std::uint64_t ml = ctx.all_edges && !pr.edges_ab ? 0 : own[wc] & ia[wc] & ib[wc];
    std::uint64_t mi = pr.act_i ? own[wc] : 0, mj = pr.act_j ? ia[wc] : 0,
                  mk = pr.act_k ? ib[wc] : 0;
    if (ctx.all_edges) mi = mj = mk = ml;
    std::uint64_t full = cand & mi & mj & mk & ml;
    std::uint64_t part = cand & (mi | mj | mk | ml) & ~full;
#if defined(CKPD_BATCHED_TETRAHEDRA)
    if constexpr (batched_tetrahedra<Model>()) {
      // Evaluated with the group's other pairs (tetrahedron_group.hpp).
      batch::PairGroup::words(t)[wc * batch::kG + static_cast<std::size_t>(group.n)] = full;
      group.pending = group.pending || full != 0;
      full = 0;
    }
#endif
    // P x Q and p x q for the sets evaluated here (the group computes its own).
    if (full | part) pr.cross(t);
    for (; full; full &= full - 1) {
      const std::size_t c = wc * 64 + static_cast<std::size_t>(std::countr_zero(full));
      // signed_V: the signed reference volume (general path) or its inverse (stencil); only
      // its sign is used below besides V or 1/V.
      double signed_V, V, inv_V;
      if constexpr (kStencil) {
        signed_V = inv_volume(c);
        inv_V = std::abs(signed_V);
        V = 0;
      } else {
        signed_V = RPQ[0] * Rx[c] + RPQ[1] * Ry[c] + RPQ[2] * Rz[c];
        V = std::abs(signed_V);
        inv_V = 0;
        if (!(V > ctx.well3)) {  // rare on lattices; degenerate sets end here
          if (V >= ctx.lo3) separate(c, 15);
          continue;
        }
      }
      const double r[3] = {rx[c], ry[c], rz[c]};
      const double v = pq[0] * r[0] + pq[1] * r[1] + pq[2] * r[2];
      const bool inverted = (kEnergy || kPenalty) && model.tetrahedron_inverted(v, signed_V);
      if constexpr (kEnergy) n_inverted += inverted;
      double f;
      if constexpr (kStencil) {
        f = model.template tetrahedron_coefficient<kPenalty>(InverseMeasure{inv_V}, v, inverted);
      } else {
        f = model.template tetrahedron_coefficient<kPenalty>(ReferenceMeasure{V}, v, inverted);
      }
      S[0] += f * r[0];
      S[1] += f * r[1];
      S[2] += f * r[2];
      F += f;
      const double kl = k3[c] * f;
      fx[c] -= kl * pq[0];
      fy[c] -= kl * pq[1];
      fz[c] -= kl * pq[2];
      if constexpr (kEnergy) {
        // The penalty's share of the energy, in V e^2 units.
        const double pen_en = kPenalty && inverted ? model.tetrahedron_penalty_measure(v) : 0.0;
        const double en = (kStencil ? model.tetrahedron_energy_measure(InverseMeasure{inv_V}, v)
                                    : model.tetrahedron_energy_measure(ReferenceMeasure{V}, v)) +
                          pen_en;
        E += en;
        slot_w[c] += e3[c] * en;
      }
      any = true;
      ++n_tetrahedra;
    }
    for (; part; part &= part - 1) {
      const std::size_t c = wc * 64 + static_cast<std::size_t>(std::countr_zero(part));
      const double signed_V =
          kStencil ? 1 / inv_volume(c) : RPQ[0] * Rx[c] + RPQ[1] * Ry[c] + RPQ[2] * Rz[c];
      const double V = std::abs(signed_V);
      const unsigned active = unsigned((mi >> (c & 63)) & 1) | unsigned((mj >> (c & 63)) & 1) << 1 |
                              unsigned((mk >> (c & 63)) & 1) << 2 |
                              unsigned((ml >> (c & 63)) & 1) << 3;
      if (kStencil || V > ctx.well3) {
        partial(c, active, signed_V);
      } else if (V >= ctx.lo3) {
        separate(c, active);
      }
    }
  }
  centre.count.tetrahedra += n_tetrahedra;
  centre.count.inverted_tetrahedra += n_inverted;
  if (!any) return;
  const double k3i = model.tetrahedron_force_weight(body.dv3[centre.index]);
  // i: +6 C3 dV3 sum f (q x r + r x p + p x q) = 6 C3 dV3 ((q - p) x S + (p x q) F).
  {
    const double s[3] = {S[0] + Si[0], S[1] + Si[1], S[2] + Si[2]};
    const double fs = F + Fi;
    const double qp[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
    centre.fx += k3i * (qp[1] * s[2] - qp[2] * s[1] + pq[0] * fs);
    centre.fy += k3i * (qp[2] * s[0] - qp[0] * s[2] + pq[1] * fs);
    centre.fz += k3i * (qp[0] * s[1] - qp[1] * s[0] + pq[2] * fs);
    if constexpr (kEnergy)
      centre.w += model.tetrahedron_energy_weight(body.dv3[centre.index]) * (E + Ei);
  }
  // j (slot a): -6 C3 dV3 q x S.
  {
    const double s[3] = {S[0] + Sj[0], S[1] + Sj[1], S[2] + Sj[2]};
    fx[a] -= k3[a] * (pb[1] * s[2] - pb[2] * s[1]);
    fy[a] -= k3[a] * (pb[2] * s[0] - pb[0] * s[2]);
    fz[a] -= k3[a] * (pb[0] * s[1] - pb[1] * s[0]);
    if constexpr (kEnergy) slot_w[a] += e3[a] * (E + Ej);
  }
  // k (slot b): -6 C3 dV3 S x p.
  {
    const double s[3] = {S[0] + Sk[0], S[1] + Sk[1], S[2] + Sk[2]};
    fx[b] -= k3[b] * (s[1] * pa[2] - s[2] * pa[1]);
    fy[b] -= k3[b] * (s[2] * pa[0] - s[0] * pa[2]);
    fz[b] -= k3[b] * (s[0] * pa[1] - s[1] * pa[0]);
    if constexpr (kEnergy) slot_w[b] += e3[b] * (E + Ek);
  }
}

}  // namespace ckpd::symmetric
