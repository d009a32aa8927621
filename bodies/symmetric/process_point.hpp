#pragma once
// Point i of the symmetric kernel: load its upper family (general or stencil path), then its
// bonds, and for each bonded pair (a, b) of its upper family the triangle {i, a, b} and the
// tetrahedra on it (a planar centre of a 2D body: its triangles in batches, triangle_batch.hpp);
// flush i's and every slot's share into the thread's whole-body arrays.
// With kEnergy the inverted sets are counted; with kPenalty they get the inversion penalty.
// With kStencil, point i's slots and reference geometry come from the body's lattice stencil.
#include "bodies/symmetric/bond_loop.hpp"
#include "bodies/symmetric/conservative_terms.hpp"
#include "bodies/symmetric/load_general.hpp"
#include "bodies/symmetric/load_stencil.hpp"
#include "bodies/symmetric/tetrahedron_loop.hpp"
#include "bodies/symmetric/triangle_batch.hpp"
#include "bodies/symmetric/triangle_term.hpp"

namespace ckpd::symmetric {

// The pairs (a, b) of point i's upper family, one by one: the triangle {i, a, b} and the
// tetrahedra on it.
template <class Model, bool kEnergy, bool kPenalty, bool kStencil, class EvaluateGroup>
inline void pair_loop(const Context<Model>& ctx, SymmetricKernelThread& t, Centre& centre,
                      std::size_t count, bool rows, [[maybe_unused]] batch::PairGroup& group,
                      [[maybe_unused]] EvaluateGroup&& evaluate_group) {
  constexpr bool kConservative = conservative_form<Model>();
  const LatticeStencil* st = ctx.stencil;
  const std::uint32_t* list = t.list.data();
  const std::size_t W = t.words;
  const std::uint64_t* own = t.own.data();
  const std::uint64_t* exact_slots = t.linear_centre ? t.exact_slots.data() : nullptr;
  if (exact_slots != nullptr && rows) mark_exact_reach(t);
  for (std::size_t n = 0; n < count && rows; ++n) {
    Pair pr;
    const std::size_t a = list[n];
    pr.a = a;
    pr.ra = &t.adj[a * W];
    // Far-field masking, i and a linear: only the pairs (a, b) with b in the exact reach hold a
    // set with an exact vertex (mark_exact_reach); none when a is outside it.
    const bool linear_a = exact_slots != nullptr && !bit(exact_slots, a);
    if (linear_a && !bit(t.exact_reach.data(), a)) continue;
    const std::uint64_t* pairs_of_a = linear_a ? reach_row_of(t, a, pr.ra) : pr.ra;
    pr.ia = t.intact_is_adjacency ? pr.ra : &t.adj_intact[a * W];
    const bool own_a = bit(own, a);
    pr.pa[0] = t.rx[a];
    pr.pa[1] = t.ry[a];
    pr.pa[2] = t.rz[a];
    for_each_pair_of<kStencil>(st, a, pairs_of_a, W, [&](std::size_t b, std::size_t number) {
      pr.only = nullptr;
      if (linear_a && !bit(exact_slots, b)) {
        // i, a, b linear: only tetrahedra with an exact fourth vertex c (in rows a and b).
        const std::uint64_t* rb = &t.adj[b * W];
        bool any = false;
        for (std::size_t w = b >> 6; w < W && !any; ++w)
          any = (pr.ra[w] & rb[w] & exact_slots[w]) != 0;
        if (!any) return;
        pr.only = exact_slots;
      }
      pr.b = b;
      pr.number = number;  // the stencil's tables
      const bool own_b = bit(own, b), bond_ab = bit(pr.ia, b);
      pr.edges_ab = own_a && own_b && bond_ab;
      pr.act_i = ctx.all_edges ? pr.edges_ab : own_a && own_b;
      pr.act_j = ctx.all_edges ? pr.edges_ab : own_a && bond_ab;
      pr.act_k = ctx.all_edges ? pr.edges_ab : own_b && bond_ab;
      pr.pb[0] = t.rx[b];
      pr.pb[1] = t.ry[b];
      pr.pb[2] = t.rz[b];
      pr.crossed = false;  // P x Q and p x q when a set evaluated here needs them
      if constexpr (Model::kTriangles) {
        if (ctx.pairs && pr.only == nullptr) {
          pr.cross(t);
          if constexpr (kConservative) {
            triangle_term_conservative<Model, kEnergy, kPenalty, kStencil>(ctx, t, centre, pr);
          } else {
            triangle_term<Model, kEnergy, kPenalty, kStencil>(ctx, t, centre, pr);
          }
        }
      }
      if constexpr (Model::kTetrahedra) {
        if (ctx.triples) {
          if constexpr (kConservative) {
            tetrahedron_loop_conservative<Model, kEnergy, kPenalty, kStencil>(ctx, t, centre, pr,
                                                                              group);
          } else {
            tetrahedron_loop<Model, kEnergy, kPenalty, kStencil>(ctx, t, centre, pr, group);
          }
#if defined(CKPD_BATCHED_TETRAHEDRA)
          if (group.pending) {
            group.pending = false;
            group.push(pr.b, t);
            if (group.n == batch::kG) evaluate_group(a);
          }
#endif
        }
      }
    });
#if defined(CKPD_BATCHED_TETRAHEDRA)
    if (group.n > 0) evaluate_group(a);
#endif
  }
}

#if defined(CKPD_BATCHED_TETRAHEDRA)
// The pairs of a centre whose family is intact (no failed bond among i and its upper
// neighbours, none of i's own), evaluated with the groups alone: every tetrahedron is active for
// all four vertices, so a pair's candidates are its group words (the stencil's triple row on
// the present slots, or rows a and b), with no per-vertex masks, flags or scalar sets. Only where
// nothing else is evaluated per pair: no triangles. The far field's masking of a linear centre
// as in pair_loop: a linear slot a visits only its pairs in the exact reach (none outside it),
// and a pair of linear slots keeps only the sets whose fourth vertex is exact.
// With `damaged` (a damaged centre under all_edges, its intact rows built): a set is active for
// all four vertices when its six bonds are intact and for none otherwise, so the same loop
// serves with the candidates cut to i-c, a-c, b-c intact, for pairs whose i-a, i-b and a-b are:
// the group words pair_loop's tetrahedron loops would store, pushed in the same order, without
// their per-pair and per-word work (28 % of a far-field sphere-disc run at m = 4.015 was that).
template <bool kStencil, class EvaluateGroup>
inline void intact_pair_loop(const ContextBase& ctx, SymmetricKernelThread& t, std::size_t count,
                             bool damaged, batch::PairGroup& group,
                             EvaluateGroup&& evaluate_group) {
  const LatticeStencil* st = ctx.stencil;
  const std::uint32_t* list = t.list.data();
  const std::size_t W = t.words;
  const std::uint64_t* present = t.present.data();
  const std::uint64_t* own = t.own.data();
  std::uint64_t* words = batch::PairGroup::words(t);
  const std::uint64_t* exact_slots = t.linear_centre ? t.exact_slots.data() : nullptr;
  if (exact_slots != nullptr) mark_exact_reach(t);
  // Intact rows: the adjacency rows when no bond near i has failed.
  auto intact_row = [&](std::size_t s) {
    return t.intact_is_adjacency ? &t.adj[s * W] : &t.adj_intact[s * W];
  };
  std::uint64_t* pairs = t.pair_row.data();
  std::uint64_t* mask = t.pair_mask.data();  // W words for all candidates, W for exact ones
  for (std::size_t n = 0; n < count; ++n) {
    const std::size_t a = list[n];
    if (damaged && !bit(own, a)) continue;  // i-a failed: no set on a is active
    const std::uint64_t* ra = &t.adj[a * W];
    const std::uint64_t* ia = damaged ? intact_row(a) : ra;
    const bool linear_a = exact_slots != nullptr && !bit(exact_slots, a);
    if (linear_a && !bit(t.exact_reach.data(), a)) continue;
    // Slot a's pairs to visit: those in its row with i-b and a-b intact (damaged) and, for a
    // linear a, with b in the exact reach; and what its pairs' candidates share: the present
    // slots (stencil) or row a, with i-c and a-c intact (damaged), and for a pair of linear
    // slots the exact ones. Per pair there remain the triple row (or row b) and b-c intact.
    const std::uint64_t* shared = kStencil ? present : ra;
    for (std::size_t w = a >> 6; w < W; ++w) {
      std::uint64_t p = ra[w], c = shared[w];
      if (damaged) {
        p &= own[w] & ia[w];
        c &= own[w] & ia[w];
      }
      if (linear_a) p &= t.exact_reach[w];
      pairs[w] = p;
      mask[w] = c;
      mask[W + w] = exact_slots != nullptr ? c & exact_slots[w] : 0;
    }
    for_each_pair_of<kStencil>(st, a, pairs, W, [&](std::size_t b, std::size_t number) {
      // The pair's candidates: the stencil's triple row, or row b, on slot a's shared mask.
      const std::uint64_t* first = kStencil ? &st->triple_row[number * W] : &t.adj[b * W];
      const std::uint64_t* m = linear_a && !bit(exact_slots, b) ? mask + W : mask;
      std::uint64_t any = 0;
      std::uint64_t* lane = words + static_cast<std::size_t>(group.n);
      const std::uint64_t* ib = damaged ? intact_row(b) : nullptr;
      // The pair's candidates are slots c > b (first_word_after).
      for (std::size_t wc = first_word_after(b, W); wc < W; ++wc) {
        std::uint64_t cand = first[wc] & m[wc];
        if (damaged) cand &= ib[wc];
        lane[wc * batch::kG] = cand;
        any |= cand;
      }
      if (!any) return;
      group.push(b, t);
      if (group.n == batch::kG) evaluate_group(a);
    });
    if (group.n > 0) evaluate_group(a);
  }
}
#endif

template <class Model, bool kEnergy, bool kPenalty, bool kStencil>
void process_point(const Context<Model>& ctx, std::size_t i, SymmetricKernelThread& t) {
  constexpr bool kSets = Model::kTriangles || Model::kTetrahedra;
  const bool rows = kSets && (ctx.pairs || ctx.triples);
  const std::size_t count =
      kStencil ? load_upper_family_stencil(ctx, i, t, rows) : load_upper_family(ctx, i, t, rows);
  if (count == 0) return;
  Centre centre;
  centre.index = static_cast<std::uint32_t>(i);
  constexpr bool kConservative = conservative_form<Model>();
  if constexpr (kConservative) {
    bond_loop_conservative<Model, kEnergy, kStencil>(ctx, t, centre);
  } else {
    bond_loop<Model, kEnergy, kStencil>(ctx, t, centre);
  }

  if constexpr (kSets) {
    if (rows && planar_centre(ctx, t)) {
      triangle_batch_point<Model, kEnergy, kPenalty, kStencil>(ctx, t, centre);
    } else {
      batch::PairGroup group;  // pairs of slot a whose tetrahedra wait for the group's evaluation
#if defined(CKPD_BATCHED_TETRAHEDRA)
      // The group's tetrahedra active for all four vertices (tetrahedron_group.hpp), weighed as the
      // force form weighs its sets; ill-conditioned ones vertex by vertex as the scalar loops do.
      double xi = 0;
      if constexpr (kConservative && Model::kTetrahedra)
        xi = ctx.body->volume[centre.index] *
             ctx.model.tetrahedron_force_weight(ctx.body->dv3[centre.index]);
      auto evaluate_group = [&](std::size_t a) {
        const double pa[3] = {t.rx[a], t.ry[a], t.rz[a]};
        const double Pa[3] = {t.Rx[a], t.Ry[a], t.Rz[a]};
        const double xab = kConservative ? xi + t.x3[a] : 0.0;
        batch::evaluate_group<Model, kEnergy, kPenalty, kConservative>(
            ctx.model, t, centre, group, a, pa, Pa, xab, ctx.well3, ctx.lo3,
            [&](int l, std::size_t c) {
              if constexpr (kConservative) {
                separate_tetrahedron_conservative<Model, kEnergy>(ctx, t, centre, a, group.b[l], c,
                                                                  15);
              } else {
                separate_tetrahedron<Model, kEnergy>(ctx, t, centre, a, group.b[l], c, 15);
              }
            });
      };
      if constexpr (batched_tetrahedra<Model>()) {
        const bool intact = intact_centre(t);
        if (!(Model::kTriangles && ctx.pairs) && ctx.triples && (intact || ctx.all_edges)) {
          intact_pair_loop<kStencil>(ctx, t, count, !intact, group, evaluate_group);
        } else {
          pair_loop<Model, kEnergy, kPenalty, kStencil>(ctx, t, centre, count, rows, group,
                                                        evaluate_group);
        }
        flush_group_lanes<Model, kEnergy>(ctx, t, centre, count);
      } else {
        pair_loop<Model, kEnergy, kPenalty, kStencil>(ctx, t, centre, count, rows, group,
                                                      evaluate_group);
      }
#else
      pair_loop<Model, kEnergy, kPenalty, kStencil>(ctx, t, centre, count, rows, group,
                                                    [](std::size_t) {});
#endif
    }
  }

  SymmetricKernelStats& s = t.stats;
  s.bonds += centre.count.bonds;
  s.triangles += centre.count.triangles;
  s.tetrahedra += centre.count.tetrahedra;
  s.triangles_per_vertex += centre.count.triangles_per_vertex;
  s.tetrahedra_per_vertex += centre.count.tetrahedra_per_vertex;
  s.inverted_triangles += centre.count.inverted_triangles;
  s.inverted_tetrahedra += centre.count.inverted_tetrahedra;
  // Flush: i's own sum and every slot's share into this thread's whole-body arrays.
  t.force[i] += Vec3(centre.fx, centre.fy, centre.fz);
  if constexpr (kEnergy) t.energy[i] += centre.w;
  const std::uint32_t* list = t.list.data();
  for (std::size_t n = 0; n < count; ++n) {
    const std::size_t a = list[n];
    t.force[t.up[a]] += Vec3(t.fx[a], t.fy[a], t.fz[a]);
    if constexpr (kEnergy) t.energy[t.up[a]] += t.w[a];
  }
}

}  // namespace ckpd::symmetric
