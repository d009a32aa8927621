#pragma once
// The energy-consistent force form (ForceForm::energy_consistent, THEORY.md section 2b) of the
// symmetric kernel's bonds, triangles and tetrahedra: each set is evaluated once, as in the
// own-family pieces (bond_loop.hpp, triangle_term.hpp, tetrahedron_loop.hpp), and acts on ALL
// its vertices with one weight, K = (1/(n+1)) sum over its active vertices c (those whose family
// holds the set and for which the damage rule leaves it on) of V^c k^c, k^c the own-family force
// weight of c (dV1^c, 2 C2 dV2^c, 6 C3 dV3^c); vertex d receives K / V^d times the set's force
// per unit force weight. Energies are the own-family shares, as in the own-family pieces (their
// volume-weighted sum is the energy E whose gradient the forces are).
#include "bodies/symmetric/pair.hpp"
#include "bodies/symmetric/tetrahedron_group.hpp"

namespace ckpd::symmetric {

template <class Model, bool kEnergy, bool kStencil>
inline void bond_loop_conservative(const Context<Model>& ctx, SymmetricKernelThread& t,
                                   Centre& centre) {
  const Body& body = *ctx.body;
  const LatticeStencil* st = ctx.stencil;
  const std::size_t W = t.words;
  const std::uint64_t* own = t.own.data();
  const std::uint32_t* __restrict up = t.up.data();
  const double* __restrict vol = t.vol.data();
  double* __restrict fx = t.fx.data();
  double* __restrict fy = t.fy.data();
  double* __restrict fz = t.fz.data();
  double* __restrict slot_w = t.w.data();
  const double dv1i = body.dv1[centre.index];
  const double Vi = body.volume[centre.index], xi = Vi * dv1i, inv_vi = 1 / Vi;
  double fix = 0, fiy = 0, fiz = 0, wi = 0;
  std::uint64_t bonds = 0;
  // Far-field masking: a linear centre's bonds to linear points are left out.
  const std::uint64_t* exact_slots = t.linear_centre ? t.exact_slots.data() : nullptr;
  for (std::size_t wd = 0; wd < W; ++wd) {
    const std::uint64_t mask = exact_slots != nullptr ? exact_slots[wd] : ~std::uint64_t{0};
    for (std::uint64_t bits = own[wd] & mask; bits; bits &= bits - 1) {
      const std::size_t a = wd * 64 + static_cast<std::size_t>(std::countr_zero(bits));
      double L, inv_L;
      if constexpr (kStencil) {
        L = st->length[a];
        inv_L = st->inv_length[a];
      } else {
        L = std::sqrt(t.Rx[a] * t.Rx[a] + t.Ry[a] * t.Ry[a] + t.Rz[a] * t.Rz[a]);
        inv_L = 1 / L;
      }
      const double rx = t.rx[a], ry = t.ry[a], rz = t.rz[a];
      const double l = std::sqrt(rx * rx + ry * ry + rz * rz);
      const double k = ctx.model.bond_coefficient(BondMeasure{L, inv_L}, l);
      const double dv1j = body.dv1[up[a]];
      const double K = 0.5 * (xi + vol[a] * dv1j);  // both ends hold the bond, both active
      const double ki = k * (K * inv_vi), kj = k * (K * t.inv_vol[a]);
      fix += ki * rx;
      fiy += ki * ry;
      fiz += ki * rz;
      fx[a] -= kj * rx;
      fy[a] -= kj * ry;
      fz[a] -= kj * rz;
      if constexpr (kEnergy) {
        const double e = 0.5 * ctx.model.bond_energy(L, ctx.model.bond_stretch(L, l));
        wi += e * dv1i;
        slot_w[a] += e * dv1j;
      }
      ++bonds;
    }
  }
  centre.fx += fix;
  centre.fy += fiy;
  centre.fz += fiz;
  if constexpr (kEnergy) centre.w += wi;
  centre.count.bonds += bonds;
}

// One vertex c's own view of a triangle (other vertices o1 < o2) or tetrahedron, with the
// reference's operations (per_vertex_terms.hpp): `seen` is c's degeneracy decision. The
// ill-conditioned path gives every vertex the sum over the perspectives c that hold the set of
// c's share times c's term at that vertex, as the reference kernel does: one perspective's
// gradients at the different vertices would differ from the reference's (and fail to sum to
// zero) by the set's rounding, which a sliver amplifies.
template <class Model>
SetTerm<3> vertex_triangle(const Context<Model>& ctx, std::uint32_t c, std::uint32_t o1,
                           std::uint32_t o2, bool& seen) {
  const Vec3 Xc = ctx.X[c];
  const Vec3 P = ctx.X[o1] - Xc, Q = ctx.X[o2] - Xc;
  const Vec3 uc = ctx.u ? ctx.u[c] : Vec3::Zero();
  const Vec3 p = ctx.u ? Vec3(P + (ctx.u[o1] - uc)) : P;
  const Vec3 q = ctx.u ? Vec3(Q + (ctx.u[o2] - uc)) : Q;
  const SetTerm<3> term = ctx.model.triangle_term(P, Q, p, q, ctx.degenerate);
  seen = !term.degenerate;
  return term;
}

template <class Model>
SetTerm<4> vertex_tetrahedron(const Context<Model>& ctx, std::uint32_t c, std::uint32_t o1,
                              std::uint32_t o2, std::uint32_t o3, bool& seen) {
  const Vec3 Xc = ctx.X[c];
  const Vec3 P = ctx.X[o1] - Xc, Q = ctx.X[o2] - Xc, R = ctx.X[o3] - Xc;
  const Vec3 uc = ctx.u ? ctx.u[c] : Vec3::Zero();
  const Vec3 p = ctx.u ? Vec3(P + (ctx.u[o1] - uc)) : P;
  const Vec3 q = ctx.u ? Vec3(Q + (ctx.u[o2] - uc)) : Q;
  const Vec3 r = ctx.u ? Vec3(R + (ctx.u[o3] - uc)) : R;
  const SetTerm<4> term = ctx.model.tetrahedron_term(P, Q, R, p, q, r, ctx.degenerate);
  seen = !term.degenerate;
  return term;
}

// An ill-conditioned triangle {i, a, b} (or one near the degeneracy threshold), energy-
// consistent form: each vertex's own view, for the active vertices (bit 0 i, 1 a, 2 b).
template <class Model, bool kEnergy>
inline void triangle_separate_conservative(const Context<Model>& ctx, SymmetricKernelThread& t,
                                           Centre& centre, std::size_t a, std::size_t b,
                                           unsigned active) {
  const Body& body = *ctx.body;
  const std::uint32_t ii = centre.index, vj = t.up[a], vk = t.up[b];
  const double Vi = body.volume[ii];
  const double k2i = ctx.model.triangle_force_weight(body.dv2[ii]);
  bool s[3] = {false, false, false};
  const SetTerm<3> tv[3] = {vertex_triangle(ctx, ii, vj, vk, s[0]),
                            vertex_triangle(ctx, vj, ii, vk, s[1]),
                            vertex_triangle(ctx, vk, ii, vj, s[2])};
  const bool act[3] = {(active & 1) != 0, (active & 2) != 0, (active & 4) != 0};
  const double k[3] = {k2i, t.k2[a], t.k2[b]};
  const double Vs[3] = {Vi, t.vol[a], t.vol[b]};
  const std::size_t slot[3] = {0, a, b};
  // Perspective c lists c first, then the other two in increasing order.
  constexpr int order[3][3] = {{0, 1, 2}, {1, 0, 2}, {2, 0, 1}};
  Vec3 f[3] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  bool any = false, inverted = false;
  for (int c = 0; c < 3; ++c) {
    s[c] = s[c] && act[c];
    if (!s[c]) continue;
    any = true;
    inverted |= tv[c].inverted;
    const double share = Vs[c] * k[c] / 3;
    for (int n = 0; n < 3; ++n) f[order[c][n]] += share * tv[c].force[static_cast<std::size_t>(n)];
  }
  if (!any) return;
  for (int d = 0; d < 3; ++d)
    centre.add<kEnergy>(t, slot[d], d == 0, f[d] / Vs[d], s[d] ? k[d] * tv[d].energy / 3 : 0.0);
  if constexpr (kEnergy) centre.count.inverted_triangles += inverted;
  ++centre.count.triangles;
  ++centre.count.triangles_per_vertex;
}

template <class Model, bool kEnergy, bool kPenalty, bool kStencil>
inline void triangle_term_conservative(const Context<Model>& ctx, SymmetricKernelThread& t,
                                       Centre& centre, const Pair& pr) {
  if (!(pr.act_i || pr.act_j || pr.act_k)) return;
  const LatticeStencil* st = ctx.stencil;
  const std::size_t a = pr.a, b = pr.b;
  const double* pa = pr.pa;
  const double* pb = pr.pb;
  const double* pq = pr.pq;
  const Body& body = *ctx.body;
  const std::uint32_t ii = centre.index;
  const double Vi = body.volume[ii];
  const double k2i = ctx.model.triangle_force_weight(body.dv2[ii]);
  double A = 0, inv_A = 0, ref_z = 0;
  if constexpr (kStencil) {
    inv_A = st->inv_area[pr.number];
    ref_z = st->area_z[pr.number];
  } else {
    A = std::sqrt(pr.RPQ[0] * pr.RPQ[0] + pr.RPQ[1] * pr.RPQ[1] + pr.RPQ[2] * pr.RPQ[2]);
    ref_z = pr.RPQ[2];
  }
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
    // The set's weight: the mean over the three vertices of V^c k2^c, active ones only.
    const double K = ((pr.act_i ? Vi * k2i : 0.0) + (pr.act_j ? t.vol[a] * t.k2[a] : 0.0) +
                      (pr.act_k ? t.vol[b] * t.k2[b] : 0.0)) /
                     3;
    double g[3];
    for (int d = 0; d < 3; ++d) g[d] = fa * pq[d];
    {
      const double ki = K / Vi;
      const double qp[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
      centre.fx += ki * (qp[1] * g[2] - qp[2] * g[1]);
      centre.fy += ki * (qp[2] * g[0] - qp[0] * g[2]);
      centre.fz += ki * (qp[0] * g[1] - qp[1] * g[0]);
      if constexpr (kEnergy)
        if (pr.act_i) centre.w += ctx.model.triangle_energy_weight(body.dv2[ii]) * en;
    }
    {
      const double ka = K / t.vol[a];
      t.fx[a] -= ka * (pb[1] * g[2] - pb[2] * g[1]);
      t.fy[a] -= ka * (pb[2] * g[0] - pb[0] * g[2]);
      t.fz[a] -= ka * (pb[0] * g[1] - pb[1] * g[0]);
      if constexpr (kEnergy)
        if (pr.act_j) t.w[a] += t.e2[a] * en;
    }
    {
      const double kb = K / t.vol[b];
      t.fx[b] += kb * (pa[1] * g[2] - pa[2] * g[1]);
      t.fy[b] += kb * (pa[2] * g[0] - pa[0] * g[2]);
      t.fz[b] += kb * (pa[0] * g[1] - pa[1] * g[0]);
      if constexpr (kEnergy)
        if (pr.act_k) t.w[b] += t.e2[b] * en;
    }
    ++centre.count.triangles;
  } else if (!kStencil && A >= ctx.lo2) {
    // Ill-conditioned or near the degeneracy threshold: each vertex's own view.
    const unsigned active = unsigned(pr.act_i) | unsigned(pr.act_j) << 1 | unsigned(pr.act_k) << 2;
    triangle_separate_conservative<Model, kEnergy>(ctx, t, centre, a, b, active);
  }
}

// An ill-conditioned tetrahedron {i, a, b, c} (or one near the degeneracy threshold): each
// vertex's view, weighed as the set's weight K (the mean over its active vertices).
template <class Model, bool kEnergy>
inline void separate_tetrahedron_conservative(const Context<Model>& ctx, SymmetricKernelThread& t,
                                              Centre& centre, std::size_t a, std::size_t b,
                                              std::size_t c, unsigned mask) {
  const Body& body = *ctx.body;
  const std::uint32_t* up = t.up.data();
  const std::uint32_t ii = centre.index, vj = up[a], vk = up[b], vl = up[c];
  const double Vi = body.volume[ii];
  const double k3i = ctx.model.tetrahedron_force_weight(body.dv3[ii]);
  bool s[4] = {false, false, false, false};
  const SetTerm<4> tv[4] = {
      vertex_tetrahedron(ctx, ii, vj, vk, vl, s[0]), vertex_tetrahedron(ctx, vj, ii, vk, vl, s[1]),
      vertex_tetrahedron(ctx, vk, ii, vj, vl, s[2]), vertex_tetrahedron(ctx, vl, ii, vj, vk, s[3])};
  const double k[4] = {k3i, t.k3[a], t.k3[b], t.k3[c]};
  const double Vs[4] = {Vi, t.vol[a], t.vol[b], t.vol[c]};
  const std::size_t slot[4] = {0, a, b, c};
  // Perspective v lists v first, then the other three in increasing order.
  constexpr int order[4][4] = {{0, 1, 2, 3}, {1, 0, 2, 3}, {2, 0, 1, 3}, {3, 0, 1, 2}};
  Vec3 f[4] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  bool seen = false, inverted = false;
  for (int v = 0; v < 4; ++v) {
    s[v] = s[v] && ((mask >> v) & 1);
    if (!s[v]) continue;
    seen = true;
    inverted |= tv[v].inverted;
    const double share = Vs[v] * k[v] / 4;
    for (int n = 0; n < 4; ++n) f[order[v][n]] += share * tv[v].force[static_cast<std::size_t>(n)];
  }
  if (!seen) return;
  for (int d = 0; d < 4; ++d)
    centre.add<kEnergy>(t, slot[d], d == 0, f[d] / Vs[d], s[d] ? k[d] * tv[d].energy / 4 : 0.0);
  if constexpr (kEnergy) centre.count.inverted_tetrahedra += inverted;
  ++centre.count.tetrahedra;
  ++centre.count.tetrahedra_per_vertex;
}

template <class Model, bool kEnergy, bool kPenalty, bool kStencil>
CKPD_TETRAHEDRON_LOOP_INLINE inline void tetrahedron_loop_conservative(
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
  const double* __restrict e3 = t.e3.data();
  const double* __restrict inv_vol = t.inv_vol.data();
  const double* __restrict x3 = t.x3.data();
  double* __restrict fx = t.fx.data();
  double* __restrict fy = t.fy.data();
  double* __restrict fz = t.fz.data();
  double* __restrict slot_w = t.w.data();
  const double* pa = pr.pa;
  const double* pb = pr.pb;
  const double* pq = pr.pq;
  const double* RPQ = pr.RPQ;
  const std::uint64_t* ia = pr.ia;
  const std::uint64_t* rb = &t.adj[b * W];
  const std::uint64_t* ib = t.intact_is_adjacency ? rb : &t.adj_intact[b * W];
  const std::uint32_t ii = centre.index;
  const double Vi = body.volume[ii];
  const double k3i = model.tetrahedron_force_weight(body.dv3[ii]);
  // V^c k3^c of i, j (slot a) and k (slot b).
  const double xi = Vi * k3i, xa = x3[a], xb = x3[b], xab = xi + xa + xb;
  // S = sum f' r and F = sum f' over the pair's tetrahedra, f' = f K with K the set's weight:
  // the forces on i, j and k follow as in tetrahedron_loop.hpp, each divided by its V.
  double S[3] = {0, 0, 0}, F = 0;
  double Ei = 0, Ej = 0, Ek = 0;  // own-family energies of i, j, k (active sets only)
  bool any = false;
  std::uint64_t n_tetrahedra = 0, n_inverted = 0;
  // A well-conditioned tetrahedron, active for the vertices in `mask`; M its reference measure.
  auto shared = [&](std::size_t c, unsigned mask, const auto& M, double signed_ref) {
    const double r[3] = {rx[c], ry[c], rz[c]};
    const double v = pq[0] * r[0] + pq[1] * r[1] + pq[2] * r[2];
    const bool inverted = (kEnergy || kPenalty) && model.tetrahedron_inverted(v, signed_ref);
    if constexpr (kEnergy) n_inverted += inverted;
    const double f = model.template tetrahedron_coefficient<kPenalty>(M, v, inverted);
    const double X = mask == 15 ? xab + x3[c]
                                : ((mask & 1) ? xi : 0.0) + ((mask & 2) ? xa : 0.0) +
                                      ((mask & 4) ? xb : 0.0) + ((mask & 8) ? x3[c] : 0.0);
    const double fk = f * (X / 4);
    S[0] += fk * r[0];
    S[1] += fk * r[1];
    S[2] += fk * r[2];
    F += fk;
    const double kl = fk * inv_vol[c];
    fx[c] -= kl * pq[0];
    fy[c] -= kl * pq[1];
    fz[c] -= kl * pq[2];
    if constexpr (kEnergy) {
      double en = model.tetrahedron_energy_measure(M, v);
      if (kPenalty && inverted) en += model.tetrahedron_penalty_measure(v);
      if (mask & 1) Ei += en;
      if (mask & 2) Ej += en;
      if (mask & 4) Ek += en;
      if (mask & 8) slot_w[c] += e3[c] * en;
    }
    any = true;
    ++n_tetrahedra;
  };
  auto separate = [&](std::size_t c, unsigned mask) {
    separate_tetrahedron_conservative<Model, kEnergy>(ctx, t, centre, a, b, c, mask);
  };
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
      cand = pr.ra[wc] & rb[wc];
    }
    if (pr.only != nullptr) cand &= pr.only[wc];
    if (!cand) continue;
    // Per vertex, the c whose tetrahedron is active for it (as in tetrahedron_loop.hpp).
    const std::uint64_t ml = ctx.all_edges && !pr.edges_ab ? 0 : own[wc] & ia[wc] & ib[wc];
    std::uint64_t mi = pr.act_i ? own[wc] : 0, mj = pr.act_j ? ia[wc] : 0,
                  mk = pr.act_k ? ib[wc] : 0;
    if (ctx.all_edges) mi = mj = mk = ml;
    std::uint64_t todo = cand & (mi | mj | mk | ml);
#if defined(CKPD_BATCHED_TETRAHEDRA)
    if constexpr (batched_tetrahedra<Model>()) {
      // The sets active for all four vertices: evaluated with the group's other pairs
      // (tetrahedron_group.hpp), the others one by one below.
      const std::uint64_t full = todo & mi & mj & mk & ml;
      todo &= ~full;
      batch::PairGroup::words(t)[wc * batch::kG + static_cast<std::size_t>(group.n)] = full;
      group.pending = group.pending || full != 0;
    }
#endif
    // P x Q and p x q for the sets evaluated here (the group computes its own).
    if (todo) pr.cross(t);
    for (; todo; todo &= todo - 1) {
      const std::size_t c = wc * 64 + static_cast<std::size_t>(std::countr_zero(todo));
      const unsigned s = static_cast<unsigned>(c & 63);
      const unsigned mask = unsigned((mi >> s) & 1) | unsigned((mj >> s) & 1) << 1 |
                            unsigned((mk >> s) & 1) << 2 | unsigned((ml >> s) & 1) << 3;
      if constexpr (kStencil) {
        // The stencil's entry is the signed 1 / V; the lattice's sets are all well conditioned.
        const double inv =
            st->inv_volume[word_triple + static_cast<std::size_t>(std::popcount(
                                             triple_row[wc] & ((std::uint64_t{1} << s) - 1)))];
        shared(c, mask, InverseMeasure{std::abs(inv)}, inv);
      } else {
        const double signed_V = RPQ[0] * Rx[c] + RPQ[1] * Ry[c] + RPQ[2] * Rz[c];
        const double V = std::abs(signed_V);
        if (V > ctx.well3) {
          shared(c, mask, ReferenceMeasure{V}, signed_V);
        } else if (V >= ctx.lo3) {
          separate(c, mask);
        }
      }
    }
  }
  centre.count.tetrahedra += n_tetrahedra;
  centre.count.inverted_tetrahedra += n_inverted;
  if (!any) return;
  {
    const double qp[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
    const double inv = 1 / Vi;
    centre.fx += inv * (qp[1] * S[2] - qp[2] * S[1] + pq[0] * F);
    centre.fy += inv * (qp[2] * S[0] - qp[0] * S[2] + pq[1] * F);
    centre.fz += inv * (qp[0] * S[1] - qp[1] * S[0] + pq[2] * F);
    if constexpr (kEnergy) centre.w += model.tetrahedron_energy_weight(body.dv3[ii]) * Ei;
  }
  {
    const double inv = inv_vol[a];
    fx[a] -= inv * (pb[1] * S[2] - pb[2] * S[1]);
    fy[a] -= inv * (pb[2] * S[0] - pb[0] * S[2]);
    fz[a] -= inv * (pb[0] * S[1] - pb[1] * S[0]);
    if constexpr (kEnergy) slot_w[a] += e3[a] * Ej;
  }
  {
    const double inv = inv_vol[b];
    fx[b] -= inv * (S[1] * pa[2] - S[2] * pa[1]);
    fy[b] -= inv * (S[2] * pa[0] - S[0] * pa[2]);
    fz[b] -= inv * (S[0] * pa[1] - S[1] * pa[0]);
    if constexpr (kEnergy) slot_w[b] += e3[b] * Ek;
  }
}

}  // namespace ckpd::symmetric
