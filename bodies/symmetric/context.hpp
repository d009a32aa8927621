#pragma once
// The symmetric kernel's shared pieces (symmetric_kernel.hpp says what it computes): the
// per-thread scratch, the context of one evaluation, bit rows, the degeneracy decisions and the
// slot fill. Internal to bodies/symmetric/ and symmetric_kernel.cpp.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "bodies/flag_scan.hpp"
#include "bodies/lattice_stencil.hpp"
#include "bodies/set_law.hpp"
#include "bodies/symmetric_kernel.hpp"

namespace ckpd {

// A lattice stencil's non-degenerate pairs (a, b) with their 1 / |A|, A_z and active vertices
// (all three: 7), for the batched triangles of complete centres (symmetric/triangle_batch.hpp).
struct FullPairs {
  const LatticeStencil* stencil = nullptr;  // the stencil they are of; null: not built
  std::size_t count = 0;
  std::vector<std::uint32_t> a, b;
  std::vector<double> inv, z;
  std::vector<std::int64_t> act;
};

// Scratch of one OpenMP thread. The point being processed is i; its "upper family" is the
// slots a = 0..m-1 holding its neighbours j > i in increasing index order (CSR order), so
// every set enumerated from i has i as its smallest vertex and is seen from no other point.
struct SymmetricKernelThread {
  // This thread's share of the whole-body result, summed over threads in a fixed order.
  std::vector<Vec3> force;
  std::vector<double> energy;

  // Per slot, structure of arrays: global index, reference and current offsets from i.
  std::vector<std::uint32_t> up;
  std::vector<double> Rx, Ry, Rz, rx, ry, rz;
  // Per slot weights: 2 C2 dV2, C2 dV2 / 3, 6 C3 dV3, 3 C3 dV3 / 4 of the slot's point; and,
  // for the energy-consistent force form, its volume V, 1 / V and V 6 C3 dV3.
  std::vector<double> k2, e2, k3, e3, vol, inv_vol, x3;
  // Per slot accumulators of the force and energy the slot's point receives from i's sets.
  std::vector<double> fx, fy, fz, w;
  // Bit rows, `words` per slot: own = bonds i-slot intact; adj row a = slots b > a that are
  // bonded to a; adj_intact row a = those of them whose bond is intact.
  std::vector<std::uint64_t> own, adj, adj_intact;
  std::size_t m = 0, words = 0;
  // Per point of the body, its slot + 1 while its rows are built (build_csr_rows), else zero.
  std::vector<std::uint64_t> slot_of;
  // The slots that hold a neighbour, as a bit row and in increasing order (`count` of them):
  // all of 0..m-1 on the general path; on the stencil path, slots are the stencil's upper
  // offsets and those outside the body are absent.
  std::vector<std::uint64_t> present;
  std::vector<std::uint32_t> list;
  std::size_t count = 0;
  // The intact rows are the adjacency rows (no failed bond among i and its upper neighbours).
  bool intact_is_adjacency = false;
  // The far field's per-set masking (SymmetricKernelWorkspace::exact_point): linear_centre, i
  // is linear and masking is on; exact_slots, the present slots whose point is exact (filled
  // only for a linear centre).
  bool linear_centre = false;
  std::vector<std::uint64_t> exact_slots;
  // With linear_centre, after the rows: the slots that begin a pair or end one with an exact
  // vertex among its later ones (mark_exact_reach).
  std::vector<std::uint64_t> exact_reach;
  // The pair loops' scratch for one slot a: the slots b it visits (pair_row) and the masks its
  // pairs' candidates share (pair_mask: all of them, then the exact ones; process_point.hpp).
  std::vector<std::uint64_t> pair_row, pair_mask;

  // The batched triangles of a planar centre (triangle_batch.hpp): one chunk of pairs, rows of
  // inputs and results, the pairs' active vertices and slots.
  std::vector<double> tri;
  std::vector<std::int64_t> tri_act;
  std::vector<std::uint32_t> tri_a, tri_b;
  // For the tests: centres that took the batch, and bit r set once a chunk of np pairs with
  // np % 8 == r has been evaluated (never reset).
  FullPairs full_pairs;  // cleared at every evaluation (compute_of)
  std::size_t tri_centres = 0;
  unsigned tri_residues = 0;

  // Grouped tetrahedra (tetrahedron_group.hpp), at most kGroupLanes pairs per group: the lanes of
  // x, y, z and energy for the centre, then for each slot, still to be weighed; zero between
  // centres (flush_lanes).
  static constexpr std::size_t kGroupLanes = 8;
  std::vector<double> lanes;
  bool lanes_used = false;
  // The group's candidate words and ill-conditioned sets (tetrahedron_group.hpp), a word per
  // lane; zero between groups.
  std::vector<std::uint64_t> group_full, group_ill;

  SymmetricKernelStats stats;
  // Bonds this thread failed in a fused evaluation (bond_only.hpp): those it counts (failed)
  // and, on a rank's restriction, those from a ghost to an owned point (ghost_failed).
  std::size_t failed = 0, ghost_failed = 0;
  // Each thread's scratch is a separate allocation, and the heap may place the next thread's
  // right after this one: two cache lines of padding keep the counters above, written at every
  // centre, off the lines that hold the next thread's vector pointers (false sharing; measured
  // on the 2D stencil path at 2 threads, docs/PERFORMANCE.md).
  char false_sharing_pad[128] = {};

  void reserve(std::size_t slots, std::size_t row_words) {
    if (Rx.size() < slots) {
      for (auto* v : {&Rx, &Ry, &Rz, &rx, &ry, &rz, &k2, &e2, &k3, &e3, &vol, &inv_vol, &x3, &fx,
                      &fy, &fz, &w})
        v->resize(slots);
      lanes.resize(4 * kGroupLanes * (slots + 1));  // new lanes are zero, old ones too
    }
    if (up.size() < slots) {
      up.resize(slots);
      list.resize(slots);
    }
    if (own.size() < row_words) {
      group_full.resize(kGroupLanes * row_words);  // new words are zero, old ones too
      group_ill.resize(kGroupLanes * row_words);
      own.resize(row_words);
      present.resize(row_words);
      exact_slots.resize(row_words);
      exact_reach.resize(row_words);
      pair_row.resize(row_words);
      pair_mask.resize(2 * row_words);
    }
    if (adj.size() < slots * row_words) {
      adj.resize(slots * row_words);
      adj_intact.resize(slots * row_words);
    }
  }
};

namespace symmetric {

// Slack on the screens below. The triple product or cross product of the same three or four
// stored points, computed from any vertex in any evaluation order, differs from the exact value
// by at most about 30 ulp of D^3 (D^2): the offsets are correctly rounded differences (relative
// error u per component) and the products add a few u of sum|terms| <= 3 sqrt3 D^3. The screens
// keep 64 eps = 128 u away from any vertex's threshold, so a screened decision is the decision
// every vertex makes; values inside the band are decided exactly, vertex by vertex.
constexpr double kRoundoff = 64 * std::numeric_limits<double>::epsilon();
constexpr double kThresholdSlack = 1e-3;

// Evaluating a set once, with its geometry seen from its first vertex, changes each vertex's
// term by the rounding of |A| or |V| (about eps D^2 or eps D^3): relative to the term, eps D^3/V
// amplified by 1/strain in f = v/|V| - sign v. For slivers (tiny V, which irregular clouds
// have) that exceeds 1e-12 of the largest force, so below these fractions of D^2, D^3 each
// vertex computes its own term exactly as the reference does. Lattices have |V| >= dx^3, about
// D^3/27 at m = 3: they never take the slow path.
// Measured on jittered clouds at 5% strain: 1e-5 leaves differences of 1e-13, 1e-4 and 1e-3
// reach the reference's own noise (1e-14); 1e-3 keeps a margin.
constexpr double kWellConditioned2 = 1e-3;
constexpr double kWellConditioned3 = 1e-3;

// What one evaluation sees of the body, independent of the force model.
struct ContextBase {
  const Body* body = nullptr;
  const Vec3* X = nullptr;
  const Vec3* u = nullptr;  // null when the body has no displacement array
  const std::size_t* offset = nullptr;
  const std::uint32_t* neighbour = nullptr;
  // Null when damage is off: the reference then loads every bond whatever its flag, and so do
  // we (FamilyScratch::load with intact_only = body.damage_enabled).
  const std::uint8_t* intact = nullptr;
  bool pairs = false, triples = false;      // the body has triangles / tetrahedra
  double degenerate = kDegenerateFraction;  // the body's degenerate_fraction
  // Body::screens: |A| > hi2 (|V| > hi3): non-degenerate for every vertex; < lo2 (lo3):
  // degenerate for every vertex; otherwise ask each vertex. |A| > well2 (|V| > well3): the set
  // is evaluated once with shared geometry; below, each vertex evaluates its own term with the
  // reference's arithmetic (>= hi2, hi3).
  double hi2 = 0, lo2 = 0, hi3 = 0, lo3 = 0;
  double well2 = 0, well3 = 0;

  // The body's lattice stencil when the kernel uses it, and, with damage, per point: none of
  // its bonds failed (0), some (kSomeFailed) or all (kAllFailed); where some, row_upper holds
  // the CSR position of its first neighbour after it.
  const LatticeStencil* stencil = nullptr;
  static constexpr std::uint8_t kSomeFailed = 1, kAllFailed = 2;
  const std::uint8_t* row_failed = nullptr;
  const std::size_t* row_upper = nullptr;
  // Stencil path: SymmetricKernelWorkspace::failed_upper (with row_failed), else null.
  const std::uint64_t* failed_upper = nullptr;

  bool bond_intact(std::size_t k) const { return intact == nullptr || intact[k] != 0; }
  // DamageRule::all_edges with damage on: a set is active for all its vertices or none.
  bool all_edges = false;
  // The far field's exact points, or null (SymmetricKernelWorkspace::exact_point).
  const std::uint8_t* exact = nullptr;
  // The general path's adjacency rows, built once (upper_rows.hpp), or null: gathered per centre.
  const UpperRows* upper_rows = nullptr;
};

// The context with the body's force model: the kernels ask it for every set's law.
template <class Model>
struct Context : ContextBase {
  Model model;
};

// Everything but the model, from the body (its screens included: set once in make_body).
ContextBase make_context_base(const Body& body);

inline bool bit(const std::uint64_t* row, std::size_t s) {
  return (row[s >> 6] >> (s & 63)) & 1;
}
inline void set_bit(std::uint64_t* row, std::size_t s) {
  row[s >> 6] |= std::uint64_t{1} << (s & 63);
}
// The reference's decisions, reproduced operation for operation (FamilyScratch::load offsets
// X^o - X^c, census_point / evaluate_point products), for vertex c and the other vertices of the
// set in increasing index order, which is the order of c's family slots.
inline bool triangle_seen(const Vec3* X, double degenerate, std::uint32_t c, std::uint32_t o1,
                          std::uint32_t o2) {
  const Vec3 Xc = X[c];
  const Vec3 P = X[o1] - Xc, Q = X[o2] - Xc;
  const double A = P.cross(Q).norm();
  return A > degenerate * P.norm() * Q.norm();
}

inline bool tetrahedron_seen(const Vec3* X, double degenerate, std::uint32_t c, std::uint32_t o1,
                             std::uint32_t o2, std::uint32_t o3) {
  const Vec3 Xc = X[c];
  const Vec3 P = X[o1] - Xc, Q = X[o2] - Xc, R = X[o3] - Xc;
  const double V = std::abs(P.dot(Q.cross(R)));
  return V > degenerate * P.norm() * Q.norm() * R.norm();
}

// Bit v set: vertex v (0 = i, 1 = j, 2 = k, 3 = l, indices increasing) counts the set as
// non-degenerate. `size` is |A| or |V| as computed from i.
inline unsigned triangle_mask(const ContextBase& ctx, double area, std::uint32_t i, std::uint32_t j,
                              std::uint32_t k) {
  if (area > ctx.hi2) return 7;
  if (area < ctx.lo2) return 0;
  const double f = ctx.degenerate;
  return unsigned(triangle_seen(ctx.X, f, i, j, k)) |
         unsigned(triangle_seen(ctx.X, f, j, i, k)) << 1 |
         unsigned(triangle_seen(ctx.X, f, k, i, j)) << 2;
}

inline unsigned tetrahedron_mask_exact(const ContextBase& ctx, std::uint32_t i, std::uint32_t j,
                                       std::uint32_t k, std::uint32_t l) {
  const double f = ctx.degenerate;
  return unsigned(tetrahedron_seen(ctx.X, f, i, j, k, l)) |
         unsigned(tetrahedron_seen(ctx.X, f, j, i, k, l)) << 1 |
         unsigned(tetrahedron_seen(ctx.X, f, k, i, j, l)) << 2 |
         unsigned(tetrahedron_seen(ctx.X, f, l, i, j, k)) << 3;
}

inline unsigned tetrahedron_mask(const ContextBase& ctx, double volume, std::uint32_t i,
                                 std::uint32_t j, std::uint32_t k, std::uint32_t l) {
  if (volume > ctx.hi3) return 15;
  if (volume < ctx.lo3) return 0;
  return tetrahedron_mask_exact(ctx, i, j, k, l);
}

// Slot a of point i's scratch for neighbour j: reference and current offsets (the same
// operations as FamilyScratch::load, so the centre i sees the same numbers), the neighbour's
// weights, and cleared accumulators.
template <class Model>
inline void fill_slot(const Context<Model>& ctx, SymmetricKernelThread& t, std::size_t a,
                      std::uint32_t j, const Vec3& Xi, const Vec3& ui) {
  const Body& body = *ctx.body;
  const Vec3 R = ctx.X[j] - Xi;
  const Vec3 r = ctx.u ? Vec3(R + (ctx.u[j] - ui)) : R;
  t.Rx[a] = R.x();
  t.Ry[a] = R.y();
  t.Rz[a] = R.z();
  t.rx[a] = r.x();
  t.ry[a] = r.y();
  t.rz[a] = r.z();
  if constexpr (Model::kTriangles) {
    t.k2[a] = ctx.model.triangle_force_weight(body.dv2[j]);
    t.e2[a] = ctx.model.triangle_energy_weight(body.dv2[j]);
  }
  // (The tetrahedron weights only for a body with tetrahedra: nothing reads them otherwise.)
  if constexpr (Model::kTetrahedra) {
    if (ctx.triples) {
      t.k3[a] = ctx.model.tetrahedron_force_weight(body.dv3[j]);
      t.e3[a] = ctx.model.tetrahedron_energy_weight(body.dv3[j]);
    }
  }
  if constexpr (conservative_form<Model>()) {
    t.vol[a] = body.volume[j];
    t.inv_vol[a] = 1 / body.volume[j];
    if constexpr (Model::kTetrahedra)
      if (ctx.triples) t.x3[a] = body.volume[j] * t.k3[a];
  }
  t.fx[a] = t.fy[a] = t.fz[a] = t.w[a] = 0;
}

// The first word of a row that can hold slots after slot b (rows of later slots only: the words
// below b's are zero). Rows of a few words are looped over whole: a trip count the branch
// predictor knows, where starting at b's word mispredicted the loop's exit at every other pair
// (a fifth of a far-field linear centre's pair-loop samples, m = 4.015 sphere-disc, two words).
inline std::size_t first_word_after(std::size_t b, std::size_t words) {
  return words <= 4 ? 0 : b >> 6;
}

// The slots b of bit row `row` of slot a (its words from a's on), in increasing order, each with
// its pair's number in the stencil's tables on the stencil path (pair_base[a] + the rank of b in
// a's stencil row; 0 on the general path): f(b, number).
template <bool kStencil, class F>
inline void for_each_pair_of(const LatticeStencil* st, std::size_t a, const std::uint64_t* row,
                             std::size_t W, F&& f) {
  std::size_t pair_rank = kStencil ? st->pair_base[a] : 0;
  for (std::size_t wb = a >> 6; wb < W; ++wb) {
    std::uint64_t stencil_row = 0;
    std::size_t word_rank = 0;
    if constexpr (kStencil) {
      stencil_row = st->adjacency[a * W + wb];
      word_rank = pair_rank;
      pair_rank += static_cast<std::size_t>(std::popcount(stencil_row));
    }
    for (std::uint64_t bits = row[wb]; bits; bits &= bits - 1) {
      const std::size_t b = wb * 64 + static_cast<std::size_t>(std::countr_zero(bits));
      const std::size_t number =
          kStencil ? word_rank + static_cast<std::size_t>(std::popcount(
                                     stencil_row & ((std::uint64_t{1} << (b & 63)) - 1)))
                   : 0;
      f(b, number);
    }
  }
}

// After a load: whether centre i is linear under the far field's masking, and then which of
// its present slots (t.list) hold exact points.
inline void mark_exact_slots(const ContextBase& ctx, SymmetricKernelThread& t, std::size_t i) {
  t.linear_centre = ctx.exact != nullptr && ctx.exact[i] == 0;
  if (!t.linear_centre) return;
  std::fill_n(t.exact_slots.begin(), t.words, 0);
  for (std::size_t n = 0; n < t.count; ++n)
    if (ctx.exact[t.up[t.list[n]]] != 0) set_bit(t.exact_slots.data(), t.list[n]);
}

// A linear centre's exact reach, once its adjacency rows are built: the exact slots and the
// slots s with an exact slot in row s. A set {i, a, b, c} (a < b < c) of a linear centre holds
// an exact vertex only where a is in the reach (a exact, or b or c exact and in row a) and, for
// a linear a, b is in it too (b exact, or c exact and in row b); the pair loops visit only
// those slots and pairs. Costs a pass over the rows per linear centre, where the pair loops
// otherwise visited every pair of a slot that reaches one exact slot (three tenths of a far-field
// sphere-disc's visited pairs at m = 4.015 belonged to such centres, counted).
inline void mark_exact_reach(SymmetricKernelThread& t) {
  const std::size_t W = t.words;
  const std::uint64_t* exact = t.exact_slots.data();
  std::uint64_t* reach = t.exact_reach.data();
  std::copy_n(exact, W, reach);
  for (std::size_t n = 0; n < t.count; ++n) {
    const std::size_t s = t.list[n];
    const std::uint64_t* row = &t.adj[s * W];
    std::uint64_t meets = 0;
    for (std::size_t w = s >> 6; w < W; ++w) meets |= row[w] & exact[w];
    if (meets != 0) set_bit(reach, s);
  }
}

// Row `row` of slot a cut to the exact reach (mark_exact_reach), in t.pair_row.
inline const std::uint64_t* reach_row_of(SymmetricKernelThread& t, std::size_t a,
                                         const std::uint64_t* row) {
  const std::uint64_t* reach = t.exact_reach.data();
  std::uint64_t* out = t.pair_row.data();
  for (std::size_t w = a >> 6; w < t.words; ++w) out[w] = row[w] & reach[w];
  return out;
}

// One word of a slot row from CSR entries [from, to) of a point's row: bit s - base of the slots
// s held by the entries' points, for base <= s < base + 64 (slot_of: a point's slot + 1, zero
// for a point that is no present slot; the unsigned difference wraps for those below). A
// gather per vector of entries (64-bit slot_of: GCC 12 vectorises the gather and the variable
// shift only with one element width).
inline std::uint64_t slot_word(const std::uint32_t* __restrict nb,
                               const std::uint64_t* __restrict slot_of, std::size_t from,
                               std::size_t to, std::uint64_t base) {
  std::uint64_t bits = 0;
#pragma omp simd reduction(| : bits)
  for (std::size_t k = from; k < to; ++k) {
    const std::uint64_t s = slot_of[nb[k]] - 1 - base;
    bits |= std::uint64_t{s < 64} << (s & 63);
  }
  return bits;
}

// Rows from the CSR rows: for each present slot a (in list order) and each later present slot b,
// whether up[b] is in H1(up[a]) (into `adjacency`, when given) and, with `intact_rows`, whether
// that bond is intact (into adj_intact; its flag read at the bond's CSR position in up[a]'s row).
// `adjacency` is asked for only on the general path, whose slots are all of 0..m-1: word w of a
// row is gathered from the entries of up[a]'s row between the points of slots 64 w and
// 64 w + 63. (A merge of the two sorted lists did this with a mispredicted branch at every step:
// 14 % of the general path's step on a 16^3 block, perf.)
inline void build_csr_rows(const ContextBase& ctx, SymmetricKernelThread& t,
                           std::uint64_t* adjacency, bool intact_rows = true) {
  const std::uint32_t* nb = ctx.neighbour;
  const std::size_t W = t.words, count = t.count;
  if (count == 0) return;
  // Grown once per body size (zero between calls: every entry set below is cleared below).
  if (t.slot_of.size() < ctx.body->size()) t.slot_of.resize(ctx.body->size(), 0);
  std::uint64_t* slot_of = t.slot_of.data();
  for (std::size_t n = 0; n < count; ++n) slot_of[t.up[t.list[n]]] = std::uint64_t{t.list[n]} + 1;
  const std::uint8_t* intact = ctx.intact;
  for (std::size_t n = 0; n < count; ++n) {
    const std::size_t a = t.list[n];
    std::uint64_t* row = adjacency != nullptr ? adjacency + a * W : nullptr;
    std::uint64_t* irow = intact_rows ? &t.adj_intact[a * W] : nullptr;
    if (irow != nullptr) std::fill_n(irow, W, 0);
    if (row != nullptr) std::fill_n(row, W, 0);
    if (n + 1 == count) break;
    const std::uint32_t j = t.up[a];
    const std::uint32_t* row_end = nb + ctx.offset[j + 1];
    if (row != nullptr) {
      const std::uint32_t* after = std::upper_bound(nb + ctx.offset[j], row_end, j);
      for (std::size_t w = a >> 6; w < W; ++w) {
        const std::uint32_t* from = W == 1 ? after : std::lower_bound(after, row_end, t.up[64 * w]);
        const std::uint32_t* to =
            std::upper_bound(from, row_end, t.up[std::min(64 * w + 63, count - 1)]);
        row[w] = slot_word(nb, slot_of, static_cast<std::size_t>(from - nb),
                           static_cast<std::size_t>(to - nb), 64 * w);
      }
    }
    if (irow == nullptr) continue;
    // The intact row: the adjacency row (built above, or copied from the upper-rows table)
    // less the bonds that failed in up[a]'s CSR row. Most rows have none, even near damage
    // (row_failed); a row whose bonds all failed is empty, as filled above (in a hole's damage
    // such rows held 44 % of the failed entries this loop visited: sphere-disc far field,
    // m = 4.015); a row with some is scanned for them from its upper part on (row_upper).
    if (ctx.row_failed != nullptr && ctx.row_failed[j] == ContextBase::kAllFailed) continue;
    std::copy_n(row != nullptr ? row : &t.adj[a * W], W, irow);
    if (intact == nullptr || (ctx.row_failed != nullptr && ctx.row_failed[j] == 0)) continue;
    // The failed entries of the row, eight flags at a time (flag_scan.hpp). Only the upper
    // entries count (points after j, as the rows hold them); points that are no slot of i have
    // slot_of zero.
    const std::size_t begin = ctx.row_failed != nullptr ? ctx.row_upper[j] : ctx.offset[j];
    const std::size_t end = ctx.offset[j + 1];
    auto clear = [&](std::size_t k) {
      const std::uint32_t x = nb[k];
      const std::uint64_t s = x > j ? slot_of[x] : 0;
      if (s != 0) irow[(s - 1) >> 6] &= ~(std::uint64_t{1} << ((s - 1) & 63));
    };
    for_each_flag_other_than(intact, begin, end, 1, clear);
  }
  for (std::size_t n = 0; n < count; ++n) slot_of[t.up[t.list[n]]] = 0;
}

}  // namespace symmetric
}  // namespace ckpd
