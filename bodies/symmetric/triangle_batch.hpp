#pragma once
// The triangles of a planar centre (issue 21): point i of a 2D body, whose slots' reference and
// current offsets all lie in the xy plane (z components zero), has only triangles {i, a, b}, and
// their area vectors are (0, 0, a_z). The batch evaluates them in three passes over chunks of
// kTriangleChunk pairs:
//   1. enumerate the pairs (a, b) of the upper family as process_point does, with their active
//      vertices, and copy their offsets and weights into structure-of-arrays rows (a complete
//      stencil centre takes the stencil's pair list, full_pairs, in place of the bit rows);
//   2. one loop without branches over the chunk: |a|, the law, and every vertex's force and
//      energy share, 4 lanes at a time for the linear law in AVX2 builds (GCC vector extensions,
//      as tetrahedron_batch.hpp), lane by lane otherwise;
//   3. add the shares to i, a and b in the pairs' order.
// Pass 2 is triangle_term (triangle_term_conservative) with the z components' zero terms left
// out: a product with a zero factor is a signed zero, and x - 0 = x, so every share is the same
// number (up to the sign of a zero) as the scalar path's, and pass 3 adds them in the scalar
// path's order: the results are the scalar path's bits. An inactive vertex's share is a zero.
// Ill-conditioned triangles (general path, |A| <= well2) are handed to the per-vertex code in
// their turn in pass 3, as the scalar path does.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>

#include "bodies/symmetric/conservative_terms.hpp"
#include "bodies/symmetric/tetrahedron_batch.hpp"
#include "bodies/symmetric/triangle_term.hpp"

namespace ckpd::symmetric {

inline constexpr std::size_t kTriangleChunk = 128;

// Test hook: false sends every centre to the scalar pair loop of process_point.
inline bool batched_triangles_enabled = true;

// Whether centre i's sets go to the batch: triangles only (no tetrahedra), no far-field masking,
// and every present slot's offsets in the xy plane.
template <class Model>
inline bool planar_centre(const Context<Model>& ctx, const SymmetricKernelThread& t) {
  if (!Model::kTriangles || !ctx.pairs || (Model::kTetrahedra && ctx.triples)) return false;
  if (!batched_triangles_enabled || t.linear_centre) return false;
  const std::uint32_t* list = t.list.data();
  bool flat = true;
  for (std::size_t n = 0; n < t.count; ++n) {
    const std::size_t a = list[n];
    flat = flat & (t.Rz[a] == 0) & (t.rz[a] == 0);
  }
  return flat;
}

namespace triangle_batch {
// Rows of a chunk: inputs, then results.
enum Row : std::size_t {
  kPax,
  kPay,
  kPbx,
  kPby,
  kRef,   // stencil: 1 / |A|; general: A_z of the reference offsets
  kRefZ,  // stencil: A_z
  kK2a,
  kK2b,
  kE2a,
  kE2b,
  kVa,
  kVb,
  kFix,  // shares: i's force (added), a's (subtracted), b's (added), energies
  kFiy,
  kFax,
  kFay,
  kFbx,
  kFby,
  kEi,
  kEa,
  kEb,
  kArea,      // general: |A|
  kInverted,  // 1: inverted
  kRows
};
}  // namespace triangle_batch

// A stencil centre whose pairs are all of the stencil's: every slot present, in slot order, and
// no failed bond among i and its neighbours (so every pair is active for all three vertices).
template <class Model>
inline bool complete_centre(const Context<Model>& ctx, const SymmetricKernelThread& t) {
  const LatticeStencil& st = *ctx.stencil;
  if (t.count != st.slots || !t.intact_is_adjacency) return false;
  const std::uint32_t* list = t.list.data();
  bool in_order = true;
  for (std::size_t n = 0; n < t.count; ++n) in_order = in_order & (list[n] == n);
  std::size_t own = 0;
  for (std::size_t w = 0; w < t.words; ++w)
    own += static_cast<std::size_t>(std::popcount(t.own[w]));
  return in_order && own == t.count;
}

// The thread's list of the stencil's non-degenerate pairs in the pair loop's order (built at an
// evaluation's first complete centre; compute_of clears it at every evaluation). The rows are
// padded to a multiple of 8 entries for the vector lanes.
template <class Model>
inline const FullPairs& full_pairs(const Context<Model>& ctx, SymmetricKernelThread& t) {
  FullPairs& full = t.full_pairs;
  const LatticeStencil* st = ctx.stencil;
  if (full.stencil == st) return full;
  // Cleared, not reassigned: the capacity stays (no allocation after the first evaluation).
  full.a.clear();
  full.b.clear();
  full.inv.clear();
  full.z.clear();
  full.act.clear();
  const std::size_t W = st->words;
  for (std::size_t a = 0; a < st->slots; ++a) {
    for_each_pair_of<true>(st, a, &st->adjacency[a * W], W, [&](std::size_t b, std::size_t number) {
      if (st->inv_area[number] == 0) return;
      full.a.push_back(static_cast<std::uint32_t>(a));
      full.b.push_back(static_cast<std::uint32_t>(b));
      full.inv.push_back(st->inv_area[number]);
      full.z.push_back(st->area_z[number]);
      full.act.push_back(7);
    });
  }
  full.count = full.a.size();
  const std::size_t padded = (full.count + 7) / 8 * 8;
  full.a.resize(padded, 0);
  full.b.resize(padded, 0);
  full.inv.resize(padded, 0.0);
  full.z.resize(padded, 0.0);
  full.act.resize(padded, 0);
  full.stencil = st;
  return full;
}

template <class Model, bool kEnergy, bool kPenalty, bool kStencil>
inline void triangle_batch_point(const Context<Model>& ctx, SymmetricKernelThread& t,
                                 Centre& centre) {
  using namespace triangle_batch;
  constexpr bool kConservative = conservative_form<Model>();
  constexpr std::size_t C = kTriangleChunk;
  if (t.tri.size() < kRows * C) {
    t.tri.assign(kRows * C, 0.0);
    t.tri_act.assign(C, 0);
    t.tri_a.assign(C, 0);
    t.tri_b.assign(C, 0);
  }
  const Body& body = *ctx.body;
  const LatticeStencil* st = ctx.stencil;
  const std::size_t W = t.words;
  const std::uint32_t* list = t.list.data();
  const std::uint64_t* own = t.own.data();
  const double* rx = t.rx.data();
  const double* ry = t.ry.data();
  const double* Rx = t.Rx.data();
  const double* Ry = t.Ry.data();
  const double* k2 = t.k2.data();
  const double* e2 = t.e2.data();
  const double* vol = t.vol.data();
  double* fx = t.fx.data();
  double* fy = t.fy.data();
  double* slot_w = t.w.data();
  double* row = t.tri.data();
  const std::uint32_t ii = centre.index;
  const double k2i = ctx.model.triangle_force_weight(body.dv2[ii]);
  const double e2i = ctx.model.triangle_energy_weight(body.dv2[ii]);
  const double Vi = body.volume[ii];
  const Model model = ctx.model;

  // Passes 2 and 3 over the first `np` pairs of the chunk.
  // The pairs' reference numbers, active vertices and slots come from the chunk's rows or, for
  // a complete centre, from the stencil's pair list (full_pairs).
  auto evaluate = [&](std::size_t np, const double* __restrict ref, const double* __restrict ref_z,
                      const std::int64_t* __restrict act, const std::uint32_t* __restrict slot_a,
                      const std::uint32_t* __restrict slot_b) {
    t.tri_residues |= 1u << (np % 8);
    double* __restrict pax = row + kPax * C;
    double* __restrict pay = row + kPay * C;
    double* __restrict pbx = row + kPbx * C;
    double* __restrict pby = row + kPby * C;
    double* __restrict k2a = row + kK2a * C;
    double* __restrict k2b = row + kK2b * C;
    double* __restrict e2a = row + kE2a * C;
    double* __restrict e2b = row + kE2b * C;
    double* __restrict va = row + kVa * C;
    double* __restrict vb = row + kVb * C;
    double* __restrict fix = row + kFix * C;
    double* __restrict fiy = row + kFiy * C;
    double* __restrict fax = row + kFax * C;
    double* __restrict fay = row + kFay * C;
    double* __restrict fbx = row + kFbx * C;
    double* __restrict fby = row + kFby * C;
    double* __restrict ei = row + kEi * C;
    double* __restrict ea = row + kEa * C;
    double* __restrict eb = row + kEb * C;
    double* __restrict area = row + kArea * C;
    double* __restrict inverted_row = row + kInverted * C;
    // Pass 2, lane by lane: the law from the model's own functions.
    auto scalar_pass = [&](std::size_t from) {
      for (std::size_t p = from; p < np; ++p) {
        // pq = p x q = (0, 0, pz); |pq| = sqrt(0 + 0 + pz^2).
        const double pz = pax[p] * pby[p] - pay[p] * pbx[p];
        const double an = std::sqrt(pz * pz);
        double rz, fa, en = 0;
        if constexpr (kStencil) {
          rz = ref_z[p];
        } else {
          rz = ref[p];
          area[p] = std::sqrt(rz * rz);
        }
        const bool inverted = (kEnergy || kPenalty) && model.triangle_inverted(pz, rz);
        auto law = [&](const auto& M) {
          fa = model.template triangle_coefficient<kPenalty>(M, an, inverted);
          if constexpr (kEnergy)
            en = model.template triangle_energy_measure<kPenalty>(M, an, inverted);
        };
        if constexpr (kStencil) {
          law(InverseMeasure{ref[p]});
        } else {
          law(ReferenceMeasure{area[p]});
        }
        inverted_row[p] = inverted ? 1.0 : 0.0;
        const double g = fa * pz;  // g = fa pq = (0, 0, g)
        const double qpx = pbx[p] - pax[p], qpy = pby[p] - pay[p];
        const std::int64_t m = act[p];
        const bool on_i = (m & 1) != 0, on_a = (m & 2) != 0, on_b = (m & 4) != 0;
        double wi, wa, wb;  // force weights
        if constexpr (kConservative) {
          const double K = ((on_i ? Vi * k2i : 0.0) + (on_a ? va[p] * k2a[p] : 0.0) +
                            (on_b ? vb[p] * k2b[p] : 0.0)) /
                           3;
          wi = K / Vi;
          wa = K / va[p];
          wb = K / vb[p];
        } else {
          wi = on_i ? k2i : 0.0;
          wa = on_a ? k2a[p] : 0.0;
          wb = on_b ? k2b[p] : 0.0;
        }
        // G_c x g with G_i = q - p, G_a = q (subtracted), G_b = p: (G_y g, -(G_x g)).
        fix[p] = wi * (qpy * g);
        fiy[p] = wi * -(qpx * g);
        fax[p] = wa * (pby[p] * g);
        fay[p] = wa * -(pbx[p] * g);
        fbx[p] = wb * (pay[p] * g);
        fby[p] = wb * -(pax[p] * g);
        if constexpr (kEnergy) {
          ei[p] = on_i ? e2i * en : 0.0;
          ea[p] = on_a ? e2a[p] * en : 0.0;
          eb[p] = on_b ? e2b[p] * en : 0.0;
        }
      }
    };
#if defined(CKPD_BATCHED_TETRAHEDRA)
    if constexpr (linear_strain_law<Model>()) {
      // The same operations kW lanes at a time (GCC vector extensions, as tetrahedron_batch.hpp):
      // CkpdLaw<LinearStrain>::triangle_coefficient and triangle_energy_measure written out, the
      // divisions done in every lane (an = 0: 1 / an is infinite and not selected). The lanes
      // past np read rows of the chunk (any finite or infinite values) and are not used.
      using batch::d4;
      using batch::i4;
      using batch::load;
      using batch::splat;
      using batch::store;
      const d4 zero = splat(0.0), one = splat(1.0);
      const bool planar = model.planar;
      for (std::size_t p = 0; p < np; p += batch::kW) {
        const d4 Pax = load(pax + p), Pay = load(pay + p), Pbx = load(pbx + p), Pby = load(pby + p);
        const d4 pz = Pax * Pby - Pay * Pbx;
        const d4 an = batch::lanes_sqrt(pz * pz);
        d4 rz, M;  // stencil: M = 1 / A; general: M = A
        if constexpr (kStencil) {
          rz = load(ref_z + p);
          M = load(ref + p);
        } else {
          rz = load(ref + p);
          M = batch::lanes_sqrt(rz * rz);
          store(area + p, M);
        }
        i4 inverted = i4{};
        if constexpr (kEnergy || kPenalty)
          if (planar) inverted = pz * rz < zero;
        d4 fa = (kStencil ? M : one / M) - (an > zero ? one / an : zero);
        if constexpr (kPenalty) fa = inverted ? fa + splat(model.pen2) / an : fa;
        d4 en = zero;
        if constexpr (kEnergy) {
          const d4 e = (kStencil ? an * M : an / M) - one;
          en = kStencil ? e * e / M : M * e * e;
          if constexpr (kPenalty) en = inverted ? en + splat(2 * model.pen2) * an : en;
          store(inverted_row + p, inverted ? one : zero);
        }
        const d4 g = fa * pz;
        const d4 qpx = Pbx - Pax, qpy = Pby - Pay;
        i4 m;
        std::memcpy(&m, act + p, sizeof m);
        const i4 on_i = (m & 1) != 0, on_a = (m & 2) != 0, on_b = (m & 4) != 0;
        d4 wi, wa, wb;
        if constexpr (kConservative) {
          const d4 Va = load(va + p), Vb = load(vb + p);
          const d4 K = ((on_i ? splat(Vi * k2i) : zero) + (on_a ? Va * load(k2a + p) : zero) +
                        (on_b ? Vb * load(k2b + p) : zero)) /
                       splat(3.0);
          wi = K / splat(Vi);
          wa = K / Va;
          wb = K / Vb;
        } else {
          wi = on_i ? splat(k2i) : zero;
          wa = on_a ? load(k2a + p) : zero;
          wb = on_b ? load(k2b + p) : zero;
        }
        store(fix + p, wi * (qpy * g));
        store(fiy + p, wi * -(qpx * g));
        store(fax + p, wa * (Pby * g));
        store(fay + p, wa * -(Pbx * g));
        store(fbx + p, wb * (Pay * g));
        store(fby + p, wb * -(Pax * g));
        if constexpr (kEnergy) {
          store(ei + p, on_i ? splat(e2i) * en : zero);
          store(ea + p, on_a ? load(e2a + p) * en : zero);
          store(eb + p, on_b ? load(e2b + p) * en : zero);
        }
      }
    } else {
      scalar_pass(0);
    }
#else
    scalar_pass(0);
#endif
    // Pass 3, in the pairs' order; a's sums stay in registers while a is the same.
    double cfx = centre.fx, cfy = centre.fy, cw = centre.w;
    std::size_t cur = slot_a[0];
    double sax = fx[cur], say = fy[cur], saw = slot_w[cur];
    std::uint64_t triangles = 0, inverted = 0;
    for (std::size_t p = 0; p < np; ++p) {
      const std::size_t a = slot_a[p], b = slot_b[p];
      if (a != cur) {
        fx[cur] = sax;
        fy[cur] = say;
        if constexpr (kEnergy) slot_w[cur] = saw;
        cur = a;
        sax = fx[a];
        say = fy[a];
        if constexpr (kEnergy) saw = slot_w[a];
      }
      if (!kStencil && !(area[p] > ctx.well2)) {
        if (area[p] >= ctx.lo2) {
          // Ill-conditioned: the per-vertex code, on the memory copies.
          fx[a] = sax;
          fy[a] = say;
          if constexpr (kEnergy) slot_w[a] = saw;
          centre.fx = cfx;
          centre.fy = cfy;
          centre.w = cw;
          const auto mask = static_cast<unsigned>(act[p]);
          if constexpr (kConservative) {
            triangle_separate_conservative<Model, kEnergy>(ctx, t, centre, a, b, mask);
          } else {
            triangle_separate<Model, kEnergy>(ctx, t, centre, a, b, mask);
          }
          cfx = centre.fx;
          cfy = centre.fy;
          cw = centre.w;
          sax = fx[a];
          say = fy[a];
          if constexpr (kEnergy) saw = slot_w[a];
        }
        continue;
      }
      cfx += fix[p];
      cfy += fiy[p];
      sax -= fax[p];
      say -= fay[p];
      fx[b] += fbx[p];
      fy[b] += fby[p];
      if constexpr (kEnergy) {
        cw += ei[p];
        saw += ea[p];
        slot_w[b] += eb[p];
        inverted += inverted_row[p] != 0;
      }
      ++triangles;
    }
    fx[cur] = sax;
    fy[cur] = say;
    if constexpr (kEnergy) slot_w[cur] = saw;
    centre.fx = cfx;
    centre.fy = cfy;
    centre.w = cw;
    centre.count.triangles += triangles;
    if constexpr (kEnergy) centre.count.inverted_triangles += inverted;
  };

  ++t.tri_centres;
  // Pass 1. The slot gather below is written out twice (complete centres, other centres) on
  // purpose: one lambda for both measured 3 % slower on the general path (kernel_bench --dim 2
  // --n 120 --nu 0.4, medians of 5 alternated, with and without always_inline; session 13).
  if constexpr (kStencil) {
    if (complete_centre(ctx, t)) {
      // Every slot present, every bond near i intact: the pairs are the stencil's, all active.
      const FullPairs& full = full_pairs(ctx, t);
      for (std::size_t q0 = 0; q0 < full.count; q0 += C) {
        const std::size_t np = std::min(C, full.count - q0);
        const std::uint32_t* fa = full.a.data() + q0;
        const std::uint32_t* fb = full.b.data() + q0;
        for (std::size_t p = 0; p < np; ++p) {
          const std::size_t a = fa[p], b = fb[p];
          row[kPax * C + p] = rx[a];
          row[kPay * C + p] = ry[a];
          row[kPbx * C + p] = rx[b];
          row[kPby * C + p] = ry[b];
          row[kK2a * C + p] = k2[a];
          row[kK2b * C + p] = k2[b];
          if constexpr (kEnergy) {
            row[kE2a * C + p] = e2[a];
            row[kE2b * C + p] = e2[b];
          }
          if constexpr (kConservative) {
            row[kVa * C + p] = vol[a];
            row[kVb * C + p] = vol[b];
          }
        }
        evaluate(np, full.inv.data() + q0, full.z.data() + q0, full.act.data() + q0, fa, fb);
      }
      return;
    }
  }
  std::int64_t* act = t.tri_act.data();
  std::uint32_t* slot_a = t.tri_a.data();
  std::uint32_t* slot_b = t.tri_b.data();
  auto evaluate_chunk = [&](std::size_t np) {
    evaluate(np, row + kRef * C, row + kRefZ * C, act, slot_a, slot_b);
  };
  std::size_t np = 0;
  for (std::size_t n = 0; n < t.count; ++n) {
    const std::size_t a = list[n];
    const std::uint64_t* ra = &t.adj[a * W];
    const std::uint64_t* ia = t.intact_is_adjacency ? ra : &t.adj_intact[a * W];
    const unsigned own_a = bit(own, a) ? 1u : 0u;
    for_each_pair_of<kStencil>(
        st, a, ra, W, [&](std::size_t b, [[maybe_unused]] std::size_t number) {
          const unsigned own_b = bit(own, b) ? 1u : 0u, bond_ab = bit(ia, b) ? 1u : 0u;
          unsigned mask = (own_a & own_b) | (own_a & bond_ab) << 1 | (own_b & bond_ab) << 2;
          if (ctx.all_edges) mask = mask == 7 ? 7 : 0;
          if (mask == 0) return;
          if constexpr (kStencil) {
            const double inv = st->inv_area[number];
            if (inv == 0) return;  // collinear: degenerate
            row[kRef * C + np] = inv;
            row[kRefZ * C + np] = st->area_z[number];
          } else {
            row[kRef * C + np] = Rx[a] * Ry[b] - Ry[a] * Rx[b];
          }
          row[kPax * C + np] = rx[a];
          row[kPay * C + np] = ry[a];
          row[kPbx * C + np] = rx[b];
          row[kPby * C + np] = ry[b];
          row[kK2a * C + np] = k2[a];
          row[kK2b * C + np] = k2[b];
          if constexpr (kEnergy) {
            row[kE2a * C + np] = e2[a];
            row[kE2b * C + np] = e2[b];
          }
          if constexpr (kConservative) {
            row[kVa * C + np] = vol[a];
            row[kVb * C + np] = vol[b];
          }
          act[np] = mask;
          slot_a[np] = static_cast<std::uint32_t>(a);
          slot_b[np] = static_cast<std::uint32_t>(b);
          if (++np == C) {
            evaluate_chunk(np);
            np = 0;
          }
        });
  }
  if (np > 0) evaluate_chunk(np);
}

}  // namespace ckpd::symmetric
