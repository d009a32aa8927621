#pragma once
// Grouped tetrahedra (docs/PERFORMANCE.md, "Tetrahedra in groups of pairs"): the tetrahedra
// {i, a, b, c} active for all four vertices, evaluated for up to kG pairs (a, b_l) of one slot a
// at once (8 with AVX-512, 4 with AVX2), one pair per lane. The loop runs over the slots c that
// hold a tetrahedron of any lane; c's offsets are broadcast, each lane has its pair's p x q,
// P x Q and sums. Against blocks of 4 slots c of one pair (the previous scheme: 2.5 live lanes
// of 4, 3.2 blocks per pair and a mispredicted exit from each pair's short loop), a group of 8
// holds 4.6 live lanes and runs one loop per eight pairs (m = 3.015, counted); the pairs' last
// lines (the forces on i, a and b from S and F) are lane-wise, with no sums across lanes.
//
// Every slot's (and the centre's) share is accumulated without its weight, one lane per pair,
// in t.lanes (kLaneRow doubles: x, y, z and energy lanes for the centre, then for each slot), and
// flush_lanes sums the lanes and applies the weights once per centre: a slot s receives
// -weight[s] times its lanes (own_family: 6 C3 dV3 of s, energy_consistent: 1 / V^s) and
// e3[s] times its energy lanes. Per tetrahedron the lanes compute what the scalar loop computes
// on the general path, operation for operation (v = p x q . r, the signed volume P x Q . R, the
// ratio v / V, the model's coefficient): on the stencil path too, whose tables the group does
// not need. Only the order of the sums over the sets differs. The pairs come from the pair loop
// (process_point.hpp) or, for a centre with an intact family, from intact_pair_loop.
#include "bodies/symmetric/tetrahedron_batch.hpp"

namespace ckpd::symmetric {

#if defined(CKPD_BATCHED_TETRAHEDRA)

namespace batch {

inline constexpr int kG = kTetrahedronGroup;  // pairs per group
static_assert(static_cast<std::size_t>(kG) <= SymmetricKernelThread::kGroupLanes,
              "the thread scratch holds the lanes of at most kGroupLanes pairs");
using gd = Vec<kG>::d;
using gi = Vec<kG>::i;
// Per slot (and the centre) in t.lanes: x, y, z and energy lanes.
inline constexpr std::size_t kLaneRow = 4 * kG;

// The pairs of one group, lane by lane; lanes past `n` are empty (no candidate words).
struct PairGroup {
  int n = 0;
  bool pending = false;  // the pair being loaded wrote candidate words to lane n
  std::size_t b[kG] = {};
  // Per lane: b's current and reference offsets (the lanes' p x q and P x Q follow with a's).
  alignas(8 * kG) double pb[3][kG] = {};
  alignas(8 * kG) double Pb[3][kG] = {};
  std::size_t first_word = 0;  // no lane has candidates below it (first_word_after the first b)

  // Lane n's candidate words (all four vertices active) in t.group_full: word w of lane l at
  // [w * kG + l], zero outside the lanes' pairs.
  static std::uint64_t* words(SymmetricKernelThread& t) { return t.group_full.data(); }
  void push(std::size_t slot, const SymmetricKernelThread& t) {
    const int l = n++;
    if (l == 0) first_word = first_word_after(slot, t.words);
    b[l] = slot;
    pb[0][l] = t.rx[slot];
    pb[1][l] = t.ry[slot];
    pb[2][l] = t.rz[slot];
    Pb[0][l] = t.Rx[slot];
    Pb[1][l] = t.Ry[slot];
    Pb[2][l] = t.Rz[slot];
  }
};

// Adds lane l of v (x, y, z) to lane l of a slot's accumulators.
inline void add_lane(double* g, int l, double x, double y, double z) {
  g[l] += x;
  g[kG + l] += y;
  g[2 * kG + l] += z;
}

// The group's tetrahedra, then its pairs' shares of i, a and the b_l. `separate(l, c)`
// evaluates an ill-conditioned set (lo3 <= |V| <= well3) of lane l vertex by vertex, as the
// scalar loop does; `xab` (energy_consistent: V k3 of i plus a's) weighs the sets by their
// vertices' mean (zero for own_family, whose sets need no weight here).
template <class Model, bool kEnergy, bool kPenalty, bool kConservative, class Separate>
inline void evaluate_group(const Model& model, SymmetricKernelThread& t, Centre& centre,
                           PairGroup& g, std::size_t a, const double pa[3], const double Pa[3],
                           double xab, double well3, double lo3, Separate&& separate) {
  const std::size_t W = t.words;
  std::uint64_t* full = PairGroup::words(t);
  const double* __restrict rx = t.rx.data();
  const double* __restrict ry = t.ry.data();
  const double* __restrict rz = t.rz.data();
  const double* __restrict Rx = t.Rx.data();
  const double* __restrict Ry = t.Ry.data();
  const double* __restrict Rz = t.Rz.data();
  const double* __restrict x3 = t.x3.data();
  double* lanes = t.lanes.data();
  // The lanes' p x q and P x Q, as Pair::cross computes them.
  const gd a0 = splatv<gd>(pa[0]), a1 = splatv<gd>(pa[1]), a2 = splatv<gd>(pa[2]);
  const gd b0 = loadv<gd>(g.pb[0]), b1 = loadv<gd>(g.pb[1]), b2 = loadv<gd>(g.pb[2]);
  const gd q0 = a1 * b2 - a2 * b1, q1 = a2 * b0 - a0 * b2, q2 = a0 * b1 - a1 * b0;
  gd R0, R1, R2;
  {
    const gd A0 = splatv<gd>(Pa[0]), A1 = splatv<gd>(Pa[1]), A2 = splatv<gd>(Pa[2]);
    const gd B0 = loadv<gd>(g.Pb[0]), B1 = loadv<gd>(g.Pb[1]), B2 = loadv<gd>(g.Pb[2]);
    R0 = A1 * B2 - A2 * B1;
    R1 = A2 * B0 - A0 * B2;
    R2 = A0 * B1 - A1 * B0;
  }
  gd xw = splatv<gd>(0.0);
  if constexpr (kConservative) {
    alignas(8 * kG) double x[kG] = {};
    for (int l = 0; l < g.n; ++l) x[l] = xab + x3[g.b[l]];
    xw = loadv<gd>(x);
  }
  const gd zero = splatv<gd>(0.0), one = splatv<gd>(1.0);
  gd s0 = zero, s1 = zero, s2 = zero, sf = zero, se = zero;
  std::uint64_t tetrahedra = 0, inverted = 0;
  bool ill_any = false;
  for (std::size_t wc = g.first_word; wc < W; ++wc) {
    std::uint64_t* fw = full + wc * kG;
    gi word;
    std::memcpy(&word, fw, sizeof word);
    std::uint64_t any = 0;
    for (int l = 0; l < kG; ++l) any |= fw[l];
    for (; any; any &= any - 1) {
      const unsigned s = static_cast<unsigned>(std::countr_zero(any));
      const std::size_t c = wc * 64 + s;
      const gi live = ((word >> static_cast<std::int64_t>(s)) & 1) != 0;
      const gd r0 = splatv<gd>(rx[c]), r1 = splatv<gd>(ry[c]), r2 = splatv<gd>(rz[c]);
      const gd v = q0 * r0 + q1 * r1 + q2 * r2;
      const gd signed_V = R0 * splatv<gd>(Rx[c]) + R1 * splatv<gd>(Ry[c]) + R2 * splatv<gd>(Rz[c]);
      const gd V = abs(signed_V);
      const gi use = live & (V > well3);
      const unsigned use_bits = bits(use);
      // Ill-conditioned lanes (lo3 <= |V| <= well3; as the scalar loop decides it): kept for
      // separate() after the loop, rare on lattices. Degenerate ones (|V| < lo3: 14 % of a
      // lattice's candidates on the general path, which has no stencil to leave them out) are
      // no sets: left out, as by the scalar loop.
      const unsigned ill = bits(live & (V >= lo3)) & ~use_bits;
      if (ill != 0) {
        for (int l = 0; l < kG; ++l)
          if ((ill >> l) & 1)
            t.group_ill[wc * kG + static_cast<std::size_t>(l)] |= std::uint64_t{1} << s;
        ill_any = true;
      }
      // tetrahedron_coefficient and tetrahedron_energy_measure (lanes outside `use` divide by 1).
      const gd M = use ? V : one;
      const gd ratio = v / M;
      const gd sgn = sign(v);
      gd f, e = zero;
      if constexpr (linear_strain_law<Model>()) {
        f = ratio - sgn;
        if constexpr (kEnergy) e = abs(ratio) - one;
      } else {
        gd factor;
        seth_hill_lanes<kEnergy>(model.strain, abs(ratio) - one, use_bits, factor, e);
        f = v != 0 ? factor * sgn : zero;
      }
      const gi inv = use & (v * signed_V < 0);  // tetrahedron_inverted
      if constexpr (kPenalty) f = inv ? f + splatv<gd>(model.pen3) * sgn : f;
      f = use ? f : zero;
      // energy_consistent: the set's weight, the mean of its vertices' V k3 (f K as shared()).
      if constexpr (kConservative) f = f * ((xw + splatv<gd>(x3[c])) / splatv<gd>(4.0));
      s0 += f * r0;
      s1 += f * r1;
      s2 += f * r2;
      sf += f;
      double* gc = lanes + kLaneRow * (c + 1);
      storev(gc, loadv<gd>(gc) + f * q0);
      storev(gc + kG, loadv<gd>(gc + kG) + f * q1);
      storev(gc + 2 * kG, loadv<gd>(gc + 2 * kG) + f * q2);
      if constexpr (kEnergy) {
        gd en = M * e * e;
        if constexpr (kPenalty) en = inv ? en + splatv<gd>(2 * model.pen3) * abs(v) : en;
        en = use ? en : zero;
        se += en;
        storev(gc + 3 * kG, loadv<gd>(gc + 3 * kG) + en);
        inverted += static_cast<std::uint64_t>(std::popcount(bits(inv)));
      }
      tetrahedra += static_cast<std::uint64_t>(std::popcount(use_bits));
    }
  }
  centre.count.tetrahedra += tetrahedra;
  if constexpr (kEnergy) centre.count.inverted_tetrahedra += inverted;
  // The pairs' last lines, lane by lane: i gets (q - p) x S + pq F, a gets q x S, b gets S x p
  // (each to be weighed and subtracted, as the scalar loop's lines).
  const gd d0 = b0 - a0, d1 = b1 - a1, d2 = b2 - a2;
  double* gcen = lanes;
  storev(gcen, loadv<gd>(gcen) + ((d1 * s2 - d2 * s1) + q0 * sf));
  storev(gcen + kG, loadv<gd>(gcen + kG) + ((d2 * s0 - d0 * s2) + q1 * sf));
  storev(gcen + 2 * kG, loadv<gd>(gcen + 2 * kG) + ((d0 * s1 - d1 * s0) + q2 * sf));
  double* ga = lanes + kLaneRow * (a + 1);
  storev(ga, loadv<gd>(ga) + (b1 * s2 - b2 * s1));
  storev(ga + kG, loadv<gd>(ga + kG) + (b2 * s0 - b0 * s2));
  storev(ga + 2 * kG, loadv<gd>(ga + 2 * kG) + (b0 * s1 - b1 * s0));
  alignas(8 * kG) double kx[kG], ky[kG], kz[kG], ke[kG];
  storev(kx, s1 * a2 - s2 * a1);
  storev(ky, s2 * a0 - s0 * a2);
  storev(kz, s0 * a1 - s1 * a0);
  if constexpr (kEnergy) {
    storev(gcen + 3 * kG, loadv<gd>(gcen + 3 * kG) + se);
    storev(ga + 3 * kG, loadv<gd>(ga + 3 * kG) + se);
    storev(ke, se);
  }
  for (int l = 0; l < g.n; ++l) {
    double* gb = lanes + kLaneRow * (g.b[l] + 1);
    add_lane(gb, l, kx[l], ky[l], kz[l]);
    if constexpr (kEnergy) gb[3 * kG + l] += ke[l];
  }
  t.lanes_used = true;
  // Clear the group's words (and the ill sets, after evaluating them vertex by vertex).
  for (std::size_t wc = g.first_word; wc < W; ++wc) {
    for (int l = 0; l < kG; ++l) {
      full[wc * kG + static_cast<std::size_t>(l)] = 0;
      if (!ill_any) continue;
      std::uint64_t& ill = t.group_ill[wc * kG + static_cast<std::size_t>(l)];
      for (std::uint64_t bitsl = ill; bitsl; bitsl &= bitsl - 1)
        separate(l, wc * 64 + static_cast<std::size_t>(std::countr_zero(bitsl)));
      ill = 0;
    }
  }
  g.n = 0;
}

// The centre's lanes summed and weighed: slot s's force -= weight[s] (its lanes), its energy
// += e3[s] (its energy lanes); i's force += weight_i (its lanes), its energy += energy_weight_i
// (its energy lanes). Zeroes the lanes for the next centre.
template <bool kEnergy>
inline void flush_lanes(SymmetricKernelThread& t, Centre& centre, std::size_t count,
                        const double* weight, double weight_i, double energy_weight_i) {
  if (!t.lanes_used) return;
  // Without energy the energy lanes were not written: they are still zero.
  constexpr std::size_t kWrittenRows = kEnergy ? 4 : 3;
  const std::uint32_t* list = t.list.data();
  double* gcen = t.lanes.data();
  for (std::size_t n = 0; n < count; ++n) {
    const std::size_t s = list[n];
    double* g = gcen + kLaneRow * (s + 1);
    t.fx[s] -= weight[s] * sum(loadv<gd>(g));
    t.fy[s] -= weight[s] * sum(loadv<gd>(g + kG));
    t.fz[s] -= weight[s] * sum(loadv<gd>(g + 2 * kG));
    if constexpr (kEnergy) t.w[s] += t.e3[s] * sum(loadv<gd>(g + 3 * kG));
    std::memset(g, 0, kWrittenRows * kG * sizeof(double));
  }
  centre.fx += weight_i * sum(loadv<gd>(gcen));
  centre.fy += weight_i * sum(loadv<gd>(gcen + kG));
  centre.fz += weight_i * sum(loadv<gd>(gcen + 2 * kG));
  if constexpr (kEnergy) centre.w += energy_weight_i * sum(loadv<gd>(gcen + 3 * kG));
  std::memset(gcen, 0, kWrittenRows * kG * sizeof(double));
  t.lanes_used = false;
}

}  // namespace batch

// The end of centre i's pairs: the groups' lanes weighed as the force form weighs a set's
// vertices (own_family: 6 C3 dV3 of the vertex; energy_consistent: 1 / V of the vertex) and added.
template <class Model, bool kEnergy>
inline void flush_group_lanes(const Context<Model>& ctx, SymmetricKernelThread& t, Centre& centre,
                              std::size_t count) {
  const Body& body = *ctx.body;
  const double dv3 = body.dv3[centre.index];
  if constexpr (conservative_form<Model>()) {
    batch::flush_lanes<kEnergy>(t, centre, count, t.inv_vol.data(), 1 / body.volume[centre.index],
                                ctx.model.tetrahedron_energy_weight(dv3));
  } else {
    batch::flush_lanes<kEnergy>(t, centre, count, t.k3.data(),
                                ctx.model.tetrahedron_force_weight(dv3),
                                ctx.model.tetrahedron_energy_weight(dv3));
  }
}

#else
namespace batch {
struct PairGroup {};  // no groups without the vector lanes
}  // namespace batch
#endif  // CKPD_BATCHED_TETRAHEDRA

// Centre i's family is intact: no failed bond among i and its upper neighbours (the intact rows
// are the adjacency) and none of i's own.
inline bool intact_centre(const SymmetricKernelThread& t) {
  if (!t.intact_is_adjacency) return false;
  for (std::size_t w = 0; w < t.words; ++w)
    if (t.own[w] != t.present[w]) return false;
  return true;
}

}  // namespace ckpd::symmetric
