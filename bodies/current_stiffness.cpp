// The CKPD stiffness bound at the current displacement (current_stiffness.hpp).
//
// How it is evaluated, and why it is cheap enough to run after every step: every bond, triangle
// and tetrahedron is visited once, from its lowest-numbered vertex (the centre's upper family,
// as the symmetric force kernel does), and gives each vertex for which it is a set of that
// vertex's own family (the damage rule decides) the term that vertex's evaluation of the set
// would give: the ratio, the measure's slope and curvature and the gradient norms are shared.
// The quantities that depend on one pair of the set's vertices only (cross products of two
// offsets, their norms, the distance between the two) are computed once per pair of the upper
// family (UpperFamily). Against the point-by-point evaluation (reference/current_stiffness.cpp,
// which this file is tested against) a tetrahedron is evaluated once instead of four times,
// with one square root (the centre's gradient norm; the other three are pair quantities) instead
// of seven; a triangle's gradient norms are edge lengths (grad_c |a| = G_c x n with n normal to
// G_c). Where the build has the force kernel's vector lanes (AVX2, AVX-512) the tetrahedra of
// one pair (a, b) are evaluated a block of slots c at a time (add_tetrahedra_lanes) and the
// triangles of one slot a a block of slots b at a time (add_triangles_lanes); builds without
// them keep the one-by-one loops (add_tetrahedra_scalar, add_triangle_scalar). Each worker sums
// into its own rows, added in worker order: deterministic per thread count.
#include "bodies/current_stiffness.hpp"

#include <omp.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <type_traits>

#include "bodies/census.hpp"
#include "bodies/ckpd_model.hpp"
#include "bodies/current_stiffness_terms.hpp"
#include "bodies/family_scratch.hpp"
#include "bodies/symmetric/tetrahedron_batch.hpp"

namespace ckpd {

namespace {

using Mat3 = Eigen::Matrix3d;
using namespace current_stiffness_detail;

// One worker's sums per point: the bonds', triangles' and tetrahedra's 3 x 3 terms (upper
// triangles: xx, xy, xz, yy, yz, zz), the isotropic terms, the shrink time, and whether a bond
// or set of the point's has collapsed (its bound is then infinite).
struct Rows {
  std::vector<double> q1, q2, q3, iso2, iso3, shrink;
  std::vector<std::uint8_t> collapsed;
  void reset(std::size_t n, bool with_shrink) {
    for (std::vector<double>* v : {&q1, &q2, &q3}) v->assign(6 * n, 0.0);
    iso2.assign(n, 0.0);
    iso3.assign(n, 0.0);
    if (with_shrink) shrink.assign(n, std::numeric_limits<double>::infinity());
    collapsed.assign(n, 0);
  }
};

// Adds f g g^T to the upper triangle q[0..5].
inline void add_dyad(double* q, double f, const Vec3& g) {
  const Vec3 fg = f * g;
  q[0] += fg.x() * g.x();
  q[1] += fg.x() * g.y();
  q[2] += fg.x() * g.z();
  q[3] += fg.y() * g.y();
  q[4] += fg.y() * g.z();
  q[5] += fg.z() * g.z();
}

// Lanes of the tetrahedra's vector path (the force kernel's group width), 1 without it.
#if defined(CKPD_BATCHED_TETRAHEDRA)
constexpr int kLanes = symmetric::kTetrahedronGroup;
#else
constexpr int kLanes = 1;
#endif

// The centre's upper family: its members with a higher index, bonded or not (a failed bond of
// the centre still leaves the set to the vertices whose own bonds hold, under centre_bonds), and
// for adjacent slots a < b (members within a horizon of each other) the pair quantities at
// a * stride + b, one array per quantity: the tetrahedron lanes read slots c, c + 1, ... of rows
// a and b as vectors (stride: n rounded up to the lanes, so that a vector never leaves a row).
// Grows only.
struct UpperFamily {
  std::size_t n = 0, words = 0, stride = 0;
  std::vector<std::uint32_t> index;
  std::vector<Vec3> ref, cur;               // offsets from the centre
  std::vector<double> cur_x, cur_y, cur_z;  // cur, one array per component (the lanes)
  std::vector<double> wx, wy, wz;           // velocities relative to the centre's
  std::vector<double> L, l;                 // reference and current lengths
  std::vector<std::uint8_t> bonded;         // the centre's bond to the slot is intact
  // Bit b of word b / 64 of row a: the centre's bond to b (bonded_bits), b adjacent to a, and
  // the members' own bond intact (intact_bits).
  std::vector<std::uint64_t> bonded_bits, adjacent, intact_bits;
  // Per adjacent pair: current cross product p_a x p_b, its norm and the norm's reciprocal (0
  // for a zero norm), reference cross product and norm, current and reference distance.
  std::vector<double> cross_x, cross_y, cross_z, cross_norm, cross_norm_inverse;
  std::vector<double> ref_cross_x, ref_cross_y, ref_cross_z, ref_cross_norm, edge, ref_edge;

  std::size_t at(std::size_t a, std::size_t b) const { return a * stride + b; }
  bool adj(std::size_t a, std::size_t b) const {
    return (adjacent[a * words + b / 64] >> (b % 64)) & 1;
  }
  bool edge_intact(std::size_t a, std::size_t b) const {
    return (intact_bits[a * words + b / 64] >> (b % 64)) & 1;
  }
  Vec3 cross(std::size_t k) const { return Vec3(cross_x[k], cross_y[k], cross_z[k]); }
  Vec3 ref_cross(std::size_t k) const {
    return Vec3(ref_cross_x[k], ref_cross_y[k], ref_cross_z[k]);
  }
  Vec3 w(std::size_t a) const { return Vec3(wx[a], wy[a], wz[a]); }

  void load(const Body& body, std::size_t i, bool sets, bool with_velocity) {
    const std::size_t begin = body.family.offset[i], end = body.family.offset[i + 1];
    const Vec3 Xi = body.reference_position[i];
    const bool has_u = !body.displacement.empty();
    const Vec3 ui = has_u ? body.displacement[i] : Vec3::Zero();
    n = 0;
    const std::size_t most =
        end - begin + static_cast<std::size_t>(kLanes);  // + kLanes: a vector past the last slot
    if (index.size() < most) {
      for (auto* v : {&ref, &cur}) v->resize(most);
      for (auto* v : {&cur_x, &cur_y, &cur_z, &wx, &wy, &wz, &L, &l}) v->resize(most, 0.0);
      index.resize(most);
      bonded.resize(most);
    }
    for (std::size_t k = begin; k < end; ++k) {
      const std::uint32_t j = body.family.neighbour[k];
      if (j <= i) continue;
      index[n] = j;
      ref[n] = body.reference_position[j] - Xi;
      cur[n] = has_u ? Vec3(ref[n] + (body.displacement[j] - ui)) : ref[n];
      cur_x[n] = cur[n].x();
      cur_y[n] = cur[n].y();
      cur_z[n] = cur[n].z();
      if (with_velocity) {
        const Vec3 wj = body.velocity[j] - body.velocity[i];
        wx[n] = wj.x();
        wy[n] = wj.y();
        wz[n] = wj.z();
      }
      L[n] = ref[n].norm();
      l[n] = cur[n].norm();
      bonded[n] = body.bond_intact[k];
      ++n;
    }
    words = (n + 63) / 64;
    bonded_bits.assign(words, 0);
    for (std::size_t a = 0; a < n; ++a)
      if (bonded[a]) bonded_bits[a / 64] |= std::uint64_t{1} << (a % 64);
    if (!sets) return;
    const std::size_t lanes = static_cast<std::size_t>(kLanes);
    stride = (n + lanes - 1) / lanes * lanes;
    if (adjacent.size() < n * words) {
      adjacent.resize(n * words);
      intact_bits.resize(n * words);
    }
    std::fill_n(adjacent.begin(), n * words, 0);
    std::fill_n(intact_bits.begin(), n * words, 0);
    const std::size_t pairs = n * stride;
    if (cross_x.size() < pairs)
      for (auto* v : {&cross_x, &cross_y, &cross_z, &cross_norm, &cross_norm_inverse, &ref_cross_x,
                      &ref_cross_y, &ref_cross_z, &ref_cross_norm, &edge, &ref_edge})
        v->resize(pairs, 0.0);
    const double limit = body.horizon * (1 + kHorizonTolerance);
    const double limit2 = limit * limit;
    for (std::size_t a = 0; a < n; ++a) {
      // The members' bonds, in a's sorted row: one merge walk for all b > a.
      const std::uint32_t* row = body.family.neighbour.data() + body.family.offset[index[a]];
      const std::uint32_t* row_end =
          body.family.neighbour.data() + body.family.offset[index[a] + 1];
      for (std::size_t b = a + 1; b < n; ++b) {
        const Vec3 d = ref[b] - ref[a];
        if (d.squaredNorm() > limit2) continue;
        const std::uint32_t target = index[b];
        const std::uint32_t* it = std::lower_bound(row, row_end, target);
        const bool has_bond = it != row_end && *it == target;
        const std::size_t k = at(a, b);
        // Not bonded although within the horizon (rounding at the horizon): no set, as the
        // members' own families would not hold it.
        if (!has_bond) continue;
        const std::uint64_t bit = std::uint64_t{1} << (b % 64);
        adjacent[a * words + b / 64] |= bit;
        if (body.bond_intact[static_cast<std::size_t>(it - body.family.neighbour.data())])
          intact_bits[a * words + b / 64] |= bit;
        const Vec3 c = cur[a].cross(cur[b]), rc = ref[a].cross(ref[b]);
        cross_x[k] = c.x();
        cross_y[k] = c.y();
        cross_z[k] = c.z();
        cross_norm[k] = c.norm();
        cross_norm_inverse[k] = cross_norm[k] > 0 ? 1 / cross_norm[k] : 0.0;
        ref_cross_x[k] = rc.x();
        ref_cross_y[k] = rc.y();
        ref_cross_z[k] = rc.z();
        ref_cross_norm[k] = rc.norm();
        edge[k] = (cur[a] - cur[b]).norm();
        ref_edge[k] = d.norm();
      }
    }
  }
};

// One centre's triangle and tetrahedron terms per vertex slot (0: the centre, 1 + a: upper slot
// a), added to the worker's rows once per centre (flush): a set's vertex terms land in a few
// contiguous slot rows instead of scattered rows of the whole body. Measured on half-resolution
// Kalthoff-Winkler at m = -1/2: 4-13 % off the bound's time (docs/PERFORMANCE.md). The 3 x 3
// terms are stored entry by entry (q2[e * slots + s], q3 the same), so that the lanes of slots
// b, b + 1, ... (triangles) or c, c + 1, ... (tetrahedra) are one vector.
struct SlotSums {
  std::size_t slots = 0;
  std::vector<double> q2, q3, iso2, iso3, shrink;
  std::vector<std::uint8_t> collapsed;
  void reset(std::size_t count, bool with_shrink) {
    slots = count;
    q2.assign(6 * slots, 0.0);
    q3.assign(6 * slots, 0.0);
    iso2.assign(slots, 0.0);
    iso3.assign(slots, 0.0);
    if (with_shrink) shrink.assign(slots, std::numeric_limits<double>::infinity());
    collapsed.assign(slots, 0);
  }
  double& q2_at(std::size_t s, int e) { return q2[static_cast<std::size_t>(e) * slots + s]; }
  double& q3_at(std::size_t s, int e) { return q3[static_cast<std::size_t>(e) * slots + s]; }
  void flush(const UpperFamily& u, std::size_t i, bool with_shrink, Rows& rows) const {
    for (std::size_t s = 0; s <= u.n; ++s) {
      const std::size_t p = s == 0 ? i : u.index[s - 1];
      for (int e = 0; e < 6; ++e) {
        rows.q2[6 * p + e] += q2[static_cast<std::size_t>(e) * slots + s];
        rows.q3[6 * p + e] += q3[static_cast<std::size_t>(e) * slots + s];
      }
      rows.iso2[p] += iso2[s];
      rows.iso3[p] += iso3[s];
      if (with_shrink) rows.shrink[p] = std::min(rows.shrink[p], shrink[s]);
      rows.collapsed[p] |= collapsed[s];
    }
  }
};

// The shared quantities of the tetrahedra {i, a, b, c} of one pair (a, b) of the centre's upper
// family.
struct PairOfSet {
  std::size_t a, b, ab;
  bool ia, ib, eab;
};

// The triangle {i, a, b} of an adjacent pair a < b of the centre's upper family.
template <class Model>
void add_triangle_scalar(const Model& model, const Body& body, const UpperFamily& u, std::size_t a,
                         std::size_t b, bool with_shrink, SlotSums& sums) {
  const bool planar = body.dimension == 2;
  const bool all_edges = body.damage_rule == DamageRule::all_edges;
  const double deg = body.degenerate_fraction;
  const std::size_t ab = u.at(a, b);
  const bool ia = u.bonded[a], ib = u.bonded[b], eab = u.edge_intact(a, b);
  // Vertex activity: the vertex's own two bonds hold (centre_bonds) or all three edges.
  const bool every = ia && ib && eab;
  bool act[3] = {all_edges ? every : ia && ib, all_edges ? every : ia && eab,
                 all_edges ? every : ib && eab};
  const double A = u.ref_cross_norm[ab];
  const double La = u.L[a], Lb = u.L[b], Lab = u.ref_edge[ab];
  // Degenerate as seen from each vertex: A against the product of its two edges.
  act[0] = act[0] && A > deg * La * Lb;
  act[1] = act[1] && A > deg * La * Lab;
  act[2] = act[2] && A > deg * Lb * Lab;
  if (!(act[0] || act[1] || act[2])) return;
  const std::size_t slot[3] = {0, 1 + a, 1 + b};
  const double an = u.cross_norm[ab];
  if (!(an > 0)) {
    for (int v = 0; v < 3; ++v)
      if (act[v]) sums.collapsed[slot[v]] = 1;
    return;
  }
  const Vec3& p = u.cur[a];
  const Vec3& q = u.cur[b];
  const Vec3 area = u.cross(ab);
  const bool inverted = model.triangle_inverted(area.z(), u.ref_cross_z[ab]);
  const Vec3 unit = area / an;
  double slope, curvature;
  tangent(model, an / A, inverted ? model.pen2 : 0.0, slope, curvature);
  // grad |a| at i, a, b: (p - q) x n, q x n, n x p; their norms are the edges opposite each
  // vertex.
  const double e[3] = {u.edge[ab], u.l[b], u.l[a]};
  const double sum = e[0] + e[1] + e[2];
  const double c = std::abs(curvature) * law_curvature(2.0, A) * sum;
  const Vec3 g[3] = {(p - q).cross(unit), q.cross(unit), unit.cross(p)};
  const double rate = with_shrink ? unit.dot(u.w(a).cross(q) + p.cross(u.w(b))) : 0.0;
  for (int v = 0; v < 3; ++v) {
    if (!act[v]) continue;
    const std::size_t sv = slot[v];
    if (e[v] > 0) {
      const double f = c / e[v];
      const Vec3 fg = f * g[v];
      const double t[6] = {fg.x() * g[v].x(), fg.x() * g[v].y(), fg.x() * g[v].z(),
                           fg.y() * g[v].y(), fg.y() * g[v].z(), fg.z() * g[v].z()};
      for (int k = 0; k < 6; ++k) sums.q2_at(sv, k) += t[k];
    }
    const double out_of_plane = planar ? 0.0 : e[v] * sum / an;
    sums.iso2[sv] += 2.0 * std::abs(slope) * (2.0 + out_of_plane);
    if (with_shrink) shrink(an, rate, sums.shrink[sv]);
  }
}

// The tetrahedra {i, a, b, c} (c > b adjacent to a and b) one by one.
template <class Model>
void add_tetrahedra_scalar(const Model& model, const Body& body, const UpperFamily& u,
                           const PairOfSet& pr, bool with_shrink, SlotSums& sums) {
  const bool all_edges = body.damage_rule == DamageRule::all_edges;
  const double deg = body.degenerate_fraction;
  const std::size_t a = pr.a, b = pr.b, ab = pr.ab;
  const bool ia = pr.ia, ib = pr.ib, eab = pr.eab;
  const std::uint64_t* row_a = &u.adjacent[a * u.words];
  const std::uint64_t* row_b = &u.adjacent[b * u.words];
  for (std::size_t wc = (b + 1) / 64; wc < u.words; ++wc) {
    std::uint64_t cbits = row_a[wc] & row_b[wc];
    if (wc == b / 64) cbits &= (b % 64 == 63) ? 0 : (~std::uint64_t{0} << (b % 64 + 1));
    for (; cbits; cbits &= cbits - 1) {
      const std::size_t c = wc * 64 + static_cast<std::size_t>(std::countr_zero(cbits));
      const std::size_t ac = u.at(a, c), bc = u.at(b, c);
      const bool ic = u.bonded[c], eac = u.edge_intact(a, c), ebc = u.edge_intact(b, c);
      const bool every = ia && ib && ic && eab && eac && ebc;
      bool act[4] = {all_edges ? every : ia && ib && ic, all_edges ? every : ia && eab && eac,
                     all_edges ? every : ib && eab && ebc, all_edges ? every : ic && eac && ebc};
      const double signed_V = u.ref[a].dot(u.ref_cross(bc)), V = std::abs(signed_V);
      const double La = u.L[a], Lb = u.L[b], Lc = u.L[c];
      const double Lab = u.ref_edge[ab], Lac = u.ref_edge[ac], Lbc = u.ref_edge[bc];
      act[0] = act[0] && V > deg * La * Lb * Lc;
      act[1] = act[1] && V > deg * La * Lab * Lac;
      act[2] = act[2] && V > deg * Lb * Lab * Lbc;
      act[3] = act[3] && V > deg * Lc * Lac * Lbc;
      if (!(act[0] || act[1] || act[2] || act[3])) continue;
      const std::size_t slot[4] = {0, 1 + a, 1 + b, 1 + c};
      // The gradients of v = p . (q x r) at i, a, b, c: -(sum of the others), q x r,
      // r x p = -(p x r), p x q.
      const Vec3 gj = u.cross(bc), gk = -u.cross(ac), gl = u.cross(ab);
      const Vec3 gi = -(gj + gk + gl);
      const double v = u.cur[a].dot(gj);
      if (v == 0) {
        for (int x = 0; x < 4; ++x)
          if (act[x]) sums.collapsed[slot[x]] = 1;
        continue;
      }
      const bool inverted = model.tetrahedron_inverted(v, signed_V);
      double slope, curvature;
      tangent(model, std::abs(v) / V, inverted ? model.pen3 : 0.0, slope, curvature);
      const double norm[4] = {gi.norm(), u.cross_norm[bc], u.cross_norm[ac], u.cross_norm[ab]};
      const double sum = norm[0] + norm[1] + norm[2] + norm[3];
      const double cc = std::abs(curvature) * law_curvature(6.0, V) * sum;
      const Vec3* g[4] = {&gi, &gj, &gk, &gl};
      // d2v / dx_x dx_d: the cross-product matrix of the edge opposite x and d; summed over
      // d, the three edges of the face opposite x.
      const double eab_ = u.edge[ab], eac_ = u.edge[ac], ebc_ = u.edge[bc];
      const double face[4] = {eab_ + eac_ + ebc_, u.l[b] + u.l[c] + ebc_, u.l[a] + u.l[c] + eac_,
                              u.l[a] + u.l[b] + eab_};
      double rate = 0;
      if (with_shrink) {
        const double dv = u.w(a).dot(gj) + u.w(b).dot(gk) + u.w(c).dot(gl);
        rate = v > 0 ? dv : -dv;
      }
      const double s6 = 6.0 * std::abs(slope);
      for (int x = 0; x < 4; ++x) {
        if (!act[x]) continue;
        const std::size_t sx = slot[x];
        if (norm[x] > 0) {
          const double f = cc / norm[x];
          const Vec3 fg = f * *g[x];
          const double t[6] = {fg.x() * g[x]->x(), fg.x() * g[x]->y(), fg.x() * g[x]->z(),
                               fg.y() * g[x]->y(), fg.y() * g[x]->z(), fg.z() * g[x]->z()};
          for (int e = 0; e < 6; ++e) sums.q3_at(sx, e) += t[e];
        }
        sums.iso3[sx] += s6 * face[x];
        if (with_shrink) shrink(std::abs(v), rate, sums.shrink[sx]);
      }
    }
  }
}

#if defined(CKPD_BATCHED_TETRAHEDRA)

// The same tetrahedra kLanes at a time (docs/PERFORMANCE.md, "The current-state bound in
// lanes"): the slots c of one aligned block of kLanes slots, masked to those adjacent to a and
// b, so that every load is a plain vector load from the pair table. The centre's, a's and b's
// terms are summed lane by lane in their slots' TermLanes, reduced across the lanes once per
// centre (summing across the lanes per pair cost 12 % of the bound); the slots c receive theirs
// as vectors. Each lane computes what add_tetrahedra_scalar computes for its set but for three
// divisions: r = |v| (1 / V) and 6 (1 / V) share one, and f = cc / |g| multiplies by the pair
// table's 1 / |g| (the bound differs by rounding, a few ulps). The measure's tangent is m =
// -1/2's rational form in vectors, m = 0's log by Highway where the build has it, any other m
// lane by lane. The order of the sums over the sets differs from the scalar loop's.
namespace lanes {

using vd = symmetric::batch::Vec<kLanes>::d;
using vi = symmetric::batch::Vec<kLanes>::i;
using symmetric::batch::bits;
using symmetric::batch::loadv;
using symmetric::batch::splatv;
using symmetric::batch::storev;

inline vd load(const std::vector<double>& v, std::size_t at) {
  return loadv<vd>(v.data() + at);
}
inline vd splat(double x) {
  return splatv<vd>(x);
}
using symmetric::batch::lanes_sqrt;
inline vi lanes_of(unsigned mask) {
  return symmetric::batch::lanes<vi>(mask);
}
inline vd vabs(vd v) {
  return symmetric::batch::abs(v);
}
inline double lane_sum(vd v) {
  return symmetric::batch::sum(v);
}
inline double lane_min(vd v) {
  alignas(8 * kLanes) double x[kLanes];
  storev(x, v);
  double s = x[0];
  for (int l = 1; l < kLanes; ++l) s = std::min(s, x[l]);
  return s;
}

// One slot's terms from many sets, lane by lane.
struct TermLanes {
  vd q[6], iso, shrink;
  void clear() {
    for (vd& x : q) x = splat(0.0);
    iso = splat(0.0);
    shrink = splat(std::numeric_limits<double>::infinity());
  }
  // Into the tetrahedra's sums (q3, iso3) or, with `pairs`, the triangles' (q2, iso2).
  void reduce_into(SlotSums& sums, std::size_t slot, bool with_shrink, bool pairs = false) const {
    for (int e = 0; e < 6; ++e)
      (pairs ? sums.q2_at(slot, e) : sums.q3_at(slot, e)) += lane_sum(q[e]);
    (pairs ? sums.iso2 : sums.iso3)[slot] += lane_sum(iso);
    if (with_shrink) sums.shrink[slot] = std::min(sums.shrink[slot], lane_min(shrink));
  }
};

// A vertex's terms of the lanes' sets: f g g^T with f = cc / |g| (zero outside the vertex's
// lanes and where |g| = 0; inverse_norm holds 1 / |g| or 0), the isotropic term and the shrink
// time (the set's, shared by its vertices).
struct VertexTerms {
  vd q[6], iso, shrink;
};
inline void vertex_terms(vi active, vd cc, vd inverse_norm, vd gx, vd gy, vd gz, vd s6face,
                         vd set_shrink, bool with_shrink, VertexTerms& t) {
  const vd zero = splat(0.0);
  const vd f = (active & (inverse_norm > 0)) ? cc * inverse_norm : zero;
  const vd fx = f * gx, fy = f * gy, fz = f * gz;
  t.q[0] = fx * gx;
  t.q[1] = fx * gy;
  t.q[2] = fx * gz;
  t.q[3] = fy * gy;
  t.q[4] = fy * gz;
  t.q[5] = fz * gz;
  t.iso = active ? s6face : zero;
  if (with_shrink) t.shrink = active ? set_shrink : splat(std::numeric_limits<double>::infinity());
}
// Adds the lanes' terms to slots s, s + 1, ... (one slot per lane): the tetrahedra's sums or,
// with `pairs`, the triangles'.
inline void add_to_slots(const VertexTerms& t, SlotSums& sums, std::size_t s, bool with_shrink,
                         bool pairs) {
  for (int e = 0; e < 6; ++e) {
    double* q = pairs ? &sums.q2_at(s, e) : &sums.q3_at(s, e);
    storev(q, loadv<vd>(q) + t.q[e]);
  }
  double* iso = pairs ? &sums.iso2[s] : &sums.iso3[s];
  storev(iso, loadv<vd>(iso) + t.iso);
  if (with_shrink) {
    const vd old = loadv<vd>(&sums.shrink[s]);
    storev(&sums.shrink[s], t.shrink < old ? t.shrink : old);
  }
}
inline void accumulate(TermLanes& acc, const VertexTerms& t, bool with_shrink) {
  for (int e = 0; e < 6; ++e) acc.q[e] += t.q[e];
  acc.iso += t.iso;
  if (with_shrink) acc.shrink = t.shrink < acc.shrink ? t.shrink : acc.shrink;
}

// The measure's slope and curvature per lane (tangent()): m = -1/2 in vector arithmetic, m = 0
// with Highway's vector logarithm where the build has it, any other m lane by lane in the lanes
// of `use` (the others are masked by the caller).
template <class Model>
inline void tangent_lanes(const Model& model, vd r, vd penalty, unsigned use, vd& slope,
                          vd& curvature) {
  if constexpr (std::is_same_v<Model, CkpdSethHillModel>) {
    if (model.strain.m == -0.5) {
      const vd ir = splat(1.0) / r, e = splat(1.0) - ir, g = ir * ir;
      slope = e * g + penalty;
      curvature = g * g - splat(2.0) * e * g * ir;
      return;
    }
#if defined(CKPD_HAVE_HIGHWAY)
    if (model.strain.m == 0) {
      // Lanes outside `use` take r = 1 (their r may be 0 or not a number).
      const vd ru = lanes_of(use) ? r : splat(1.0);
      const vd e = symmetric::batch::log_lanes(ru), ir = splat(1.0) / ru;
      slope = e * ir + penalty;
      curvature = (splat(1.0) - e) * ir * ir;
      return;
    }
#endif
  }
  alignas(8 * kLanes) double rl[kLanes], pl[kLanes], sl[kLanes] = {}, cl[kLanes] = {};
  storev(rl, r);
  storev(pl, penalty);
  for (; use; use &= use - 1) {
    const int l = std::countr_zero(use);
    tangent(model, rl[l], pl[l], sl[l], cl[l]);
  }
  slope = loadv<vd>(sl);
  curvature = loadv<vd>(cl);
}

}  // namespace lanes

template <class Model>
void add_tetrahedra_lanes(const Model& model, const Body& body, const UpperFamily& u,
                          const PairOfSet& pr, bool with_shrink, SlotSums& sums,
                          lanes::TermLanes* slot_lanes) {
  using namespace lanes;
  const bool all_edges = body.damage_rule == DamageRule::all_edges;
  const double deg = body.degenerate_fraction;
  const std::size_t a = pr.a, b = pr.b, ab = pr.ab;
  const std::uint64_t* row_a = &u.adjacent[a * u.words];
  const std::uint64_t* row_b = &u.adjacent[b * u.words];
  const std::uint64_t* intact_a = &u.intact_bits[a * u.words];
  const std::uint64_t* intact_b = &u.intact_bits[b * u.words];
  const unsigned lane_mask = (1u << kLanes) - 1;
  // Per pair: the broadcast quantities.
  const double La = u.L[a], Lb = u.L[b], Lab = u.ref_edge[ab];
  const vd deg_ab = splat(deg * La * Lb), deg_a = splat(deg * La * Lab),
           deg_b = splat(deg * Lb * Lab), degv = splat(deg);
  const vd Pa0 = splat(u.ref[a].x()), Pa1 = splat(u.ref[a].y()), Pa2 = splat(u.ref[a].z());
  const vd pa0 = splat(u.cur[a].x()), pa1 = splat(u.cur[a].y()), pa2 = splat(u.cur[a].z());
  const vd glx = splat(u.cross_x[ab]), gly = splat(u.cross_y[ab]), glz = splat(u.cross_z[ab]);
  const vd n3 = splat(u.cross_norm[ab]), i3 = splat(u.cross_norm_inverse[ab]);
  const vd eab_v = splat(u.edge[ab]);
  const vd la = splat(u.l[a]), lb = splat(u.l[b]);
  const vd face3 = splat(u.l[a] + u.l[b] + u.edge[ab]);
  const vd wax = splat(u.wx[a]), way = splat(u.wy[a]), waz = splat(u.wz[a]);
  const vd wbx = splat(u.wx[b]), wby = splat(u.wy[b]), wbz = splat(u.wz[b]);
  const vd pen3 = splat(model.pen3), zero = splat(0.0);
  TermLanes& centre = slot_lanes[0];
  TermLanes& at_a = slot_lanes[1 + a];
  TermLanes& at_b = slot_lanes[1 + b];
  VertexTerms t;
  for (std::size_t wc = (b + 1) / 64; wc < u.words; ++wc) {
    std::uint64_t cbits = row_a[wc] & row_b[wc];
    if (wc == b / 64) cbits &= (b % 64 == 63) ? 0 : (~std::uint64_t{0} << (b % 64 + 1));
    while (cbits) {
      const unsigned base = static_cast<unsigned>(std::countr_zero(cbits)) & ~(kLanes - 1u);
      const unsigned live = static_cast<unsigned>(cbits >> base) & lane_mask;
      cbits &= ~(std::uint64_t{lane_mask} << base);
      const std::size_t c0 = wc * 64 + base;
      const unsigned ic = static_cast<unsigned>(u.bonded_bits[wc] >> base) & live;
      const unsigned eac = static_cast<unsigned>(intact_a[wc] >> base) & live;
      const unsigned ebc = static_cast<unsigned>(intact_b[wc] >> base) & live;
      unsigned act[4];
      if (all_edges) {
        const unsigned every = pr.ia && pr.ib && pr.eab ? ic & eac & ebc : 0u;
        act[0] = act[1] = act[2] = act[3] = every;
      } else {
        act[0] = pr.ia && pr.ib ? ic : 0u;
        act[1] = pr.ia && pr.eab ? eac : 0u;
        act[2] = pr.ib && pr.eab ? ebc : 0u;
        act[3] = ic & eac & ebc;
      }
      if ((act[0] | act[1] | act[2] | act[3]) == 0) continue;
      const std::size_t ac = u.at(a, c0), bc = u.at(b, c0);
      const vd signed_V = Pa0 * load(u.ref_cross_x, bc) + Pa1 * load(u.ref_cross_y, bc) +
                          Pa2 * load(u.ref_cross_z, bc);
      const vd V = vabs(signed_V);
      const vd Lc = load(u.L, c0), Lac = load(u.ref_edge, ac), Lbc = load(u.ref_edge, bc);
      act[0] &= bits(V > deg_ab * Lc);
      act[1] &= bits(V > deg_a * Lac);
      act[2] &= bits(V > deg_b * Lbc);
      act[3] &= bits(V > degv * Lc * Lac * Lbc);
      unsigned any = act[0] | act[1] | act[2] | act[3];
      if (any == 0) continue;
      // Gradients of v at i, a, b, c (gl, c's, is the pair's p_a x p_b).
      const vd gjx = load(u.cross_x, bc), gjy = load(u.cross_y, bc), gjz = load(u.cross_z, bc);
      const vd gkx = -load(u.cross_x, ac), gky = -load(u.cross_y, ac), gkz = -load(u.cross_z, ac);
      const vd gix = -(gjx + gkx + glx), giy = -(gjy + gky + gly), giz = -(gjz + gkz + glz);
      const vd v = pa0 * gjx + pa1 * gjy + pa2 * gjz;
      if (const unsigned flat = bits(v == 0) & any; flat != 0) {
        // Collapsed sets: their active vertices' bounds are infinite (rare: one by one).
        for (unsigned f = flat; f; f &= f - 1) {
          const unsigned l = static_cast<unsigned>(std::countr_zero(f));
          const std::size_t slot[4] = {0, 1 + a, 1 + b, 1 + c0 + l};
          for (int x = 0; x < 4; ++x)
            if ((act[x] >> l) & 1) sums.collapsed[slot[x]] = 1;
        }
        for (unsigned& m : act) m &= ~flat;
        any &= ~flat;
        if (any == 0) continue;
      }
      const vd penalty = (v * signed_V < 0) ? pen3 : zero;
      const vd absv = vabs(v);
      // Three divisions per block (1 / V, 1 / |g_i| and, in tangent_lanes, m = -1/2's 1 / r);
      // the pair norms' reciprocals come from the pair table.
      const vd inverse_V = splat(1.0) / V;
      vd slope, curvature;
      tangent_lanes(model, absv * inverse_V, penalty, any, slope, curvature);
      const vd n0 = lanes_sqrt(gix * gix + giy * giy + giz * giz);
      const vd i0 = n0 > 0 ? splat(1.0) / n0 : zero;
      const vd i1 = load(u.cross_norm_inverse, bc), i2 = load(u.cross_norm_inverse, ac);
      const vd sum = n0 + load(u.cross_norm, bc) + load(u.cross_norm, ac) + n3;
      const vd cc = vabs(curvature) * (splat(6.0) * inverse_V) * sum;
      const vd eac_v = load(u.edge, ac), ebc_v = load(u.edge, bc), lc = load(u.l, c0);
      const vd s6 = splat(6.0) * vabs(slope);
      vd set_shrink = zero;
      if (with_shrink) {
        const vd wcx = load(u.wx, c0), wcy = load(u.wy, c0), wcz = load(u.wz, c0);
        const vd dv = (wax * gjx + way * gjy + waz * gjz) + (wbx * gkx + wby * gky + wbz * gkz) +
                      (wcx * glx + wcy * gly + wcz * glz);
        const vd rate = v > 0 ? dv : -dv;
        set_shrink = rate < 0 ? absv / -rate : splat(std::numeric_limits<double>::infinity());
      }
      if (act[0]) {
        vertex_terms(lanes_of(act[0]), cc, i0, gix, giy, giz, s6 * (eab_v + eac_v + ebc_v),
                     set_shrink, with_shrink, t);
        accumulate(centre, t, with_shrink);
      }
      if (act[1]) {
        vertex_terms(lanes_of(act[1]), cc, i1, gjx, gjy, gjz, s6 * (lb + lc + ebc_v), set_shrink,
                     with_shrink, t);
        accumulate(at_a, t, with_shrink);
      }
      if (act[2]) {
        vertex_terms(lanes_of(act[2]), cc, i2, gkx, gky, gkz, s6 * (la + lc + eac_v), set_shrink,
                     with_shrink, t);
        accumulate(at_b, t, with_shrink);
      }
      if (act[3]) {
        // Slots 1 + c0, ..., one vector per entry.
        vertex_terms(lanes_of(act[3]), cc, i3, glx, gly, glz, s6 * face3, set_shrink, with_shrink,
                     t);
        add_to_slots(t, sums, 1 + c0, with_shrink, false);
      }
    }
  }
}

// The triangles {i, a, b} of slot a, kLanes slots b at a time (aligned blocks masked to those
// adjacent to a and above it), as add_triangle_scalar computes each but for the divisions by
// |a| (one reciprocal) and the order of the sums: i's and a's terms in their slots' TermLanes,
// b's as vectors.
template <class Model>
void add_triangles_lanes(const Model& model, const Body& body, const UpperFamily& u, std::size_t a,
                         bool with_shrink, SlotSums& sums, lanes::TermLanes* slot_lanes) {
  using namespace lanes;
  const bool planar = body.dimension == 2;
  const bool all_edges = body.damage_rule == DamageRule::all_edges;
  const double deg = body.degenerate_fraction;
  const std::uint64_t* row_a = &u.adjacent[a * u.words];
  const std::uint64_t* intact_a = &u.intact_bits[a * u.words];
  const unsigned lane_mask = (1u << kLanes) - 1;
  const bool ia = u.bonded[a];
  const double La = u.L[a];
  const vd deg_a = splat(deg * La), degv = splat(deg), zero = splat(0.0), one = splat(1.0);
  const vd px = splat(u.cur[a].x()), py = splat(u.cur[a].y()), pz = splat(u.cur[a].z());
  const vd wax = splat(u.wx[a]), way = splat(u.wy[a]), waz = splat(u.wz[a]);
  const vd la = splat(u.l[a]), pen2 = splat(model.pen2);
  TermLanes& centre = slot_lanes[0];
  TermLanes& at_a = slot_lanes[1 + a];
  VertexTerms t;
  for (std::size_t wb = (a + 1) / 64; wb < u.words; ++wb) {
    std::uint64_t bbits = row_a[wb];
    if (wb == a / 64) bbits &= (a % 64 == 63) ? 0 : (~std::uint64_t{0} << (a % 64 + 1));
    while (bbits) {
      const unsigned base = static_cast<unsigned>(std::countr_zero(bbits)) & ~(kLanes - 1u);
      const unsigned live = static_cast<unsigned>(bbits >> base) & lane_mask;
      bbits &= ~(std::uint64_t{lane_mask} << base);
      const std::size_t b0 = wb * 64 + base, ab = u.at(a, b0);
      const unsigned ib = static_cast<unsigned>(u.bonded_bits[wb] >> base) & live;
      const unsigned eab = static_cast<unsigned>(intact_a[wb] >> base) & live;
      unsigned act[3];
      if (all_edges) {
        act[0] = act[1] = act[2] = ia ? ib & eab : 0u;
      } else {
        act[0] = ia ? ib : 0u;
        act[1] = ia ? eab : 0u;
        act[2] = ib & eab;
      }
      if ((act[0] | act[1] | act[2]) == 0) continue;
      const vd A = load(u.ref_cross_norm, ab), Lb = load(u.L, b0), Lab = load(u.ref_edge, ab);
      act[0] &= bits(A > deg_a * Lb);
      act[1] &= bits(A > deg_a * Lab);
      act[2] &= bits(A > degv * Lb * Lab);
      unsigned any = act[0] | act[1] | act[2];
      if (any == 0) continue;
      const vd an = load(u.cross_norm, ab);
      if (const unsigned flat = ~bits(an > 0) & any; flat != 0) {
        // Collapsed triangles: their active vertices' bounds are infinite (rare).
        for (unsigned f = flat; f; f &= f - 1) {
          const unsigned l = static_cast<unsigned>(std::countr_zero(f));
          const std::size_t slot[3] = {0, 1 + a, 1 + b0 + l};
          for (int v = 0; v < 3; ++v)
            if ((act[v] >> l) & 1) sums.collapsed[slot[v]] = 1;
        }
        for (unsigned& m : act) m &= ~flat;
        any &= ~flat;
        if (any == 0) continue;
      }
      const vd ax = load(u.cross_x, ab), ay = load(u.cross_y, ab), az = load(u.cross_z, ab);
      const vd penalty = planar ? ((az * load(u.ref_cross_z, ab) < 0) ? pen2 : zero) : zero;
      // Zero in lanes without a triangle (|a| = 0 there would make the unit normal, and with it
      // the masked lanes' f g g^T, not a number).
      const vd inverse_an = an > 0 ? one / an : zero;
      const vd nx = ax * inverse_an, ny = ay * inverse_an, nz = az * inverse_an;
      vd slope, curvature;
      tangent_lanes(model, an / A, penalty, any, slope, curvature);
      const vd qx = load(u.cur_x, b0), qy = load(u.cur_y, b0), qz = load(u.cur_z, b0);
      const vd e0 = load(u.edge, ab), e1 = load(u.l, b0);
      const vd sum = e0 + e1 + la;
      const vd c = vabs(curvature) * (splat(2.0) / A) * sum;
      const vd iso_scale = splat(2.0) * vabs(slope);
      // grad |a| at i, a, b: (p - q) x n, q x n, n x p.
      const vd dx = px - qx, dy = py - qy, dz = pz - qz;
      const vd g0x = dy * nz - dz * ny, g0y = dz * nx - dx * nz, g0z = dx * ny - dy * nx;
      const vd g1x = qy * nz - qz * ny, g1y = qz * nx - qx * nz, g1z = qx * ny - qy * nx;
      const vd g2x = ny * pz - nz * py, g2y = nz * px - nx * pz, g2z = nx * py - ny * px;
      vd set_shrink = zero;
      if (with_shrink) {
        const vd wbx = load(u.wx, b0), wby = load(u.wy, b0), wbz = load(u.wz, b0);
        // unit . (w_a x q + p x w_b)
        const vd sx = (way * qz - waz * qy) + (py * wbz - pz * wby);
        const vd sy = (waz * qx - wax * qz) + (pz * wbx - px * wbz);
        const vd sz = (wax * qy - way * qx) + (px * wby - py * wbx);
        const vd rate = nx * sx + ny * sy + nz * sz;
        set_shrink = rate < 0 ? an / -rate : splat(std::numeric_limits<double>::infinity());
      }
      auto vertex = [&](unsigned mask, vd e, vd gx, vd gy, vd gz) {
        const vd inverse_e = e > 0 ? one / e : zero;
        const vd out_of_plane = planar ? zero : e * sum * inverse_an;
        vertex_terms(lanes_of(mask), c, inverse_e, gx, gy, gz,
                     iso_scale * (splat(2.0) + out_of_plane), set_shrink, with_shrink, t);
      };
      if (act[0]) {
        vertex(act[0], e0, g0x, g0y, g0z);
        accumulate(centre, t, with_shrink);
      }
      if (act[1]) {
        vertex(act[1], e1, g1x, g1y, g1z);
        accumulate(at_a, t, with_shrink);
      }
      if (act[2]) {
        // Slots 1 + b0, ..., one vector per entry.
        vertex(act[2], la, g2x, g2y, g2z);
        add_to_slots(t, sums, 1 + b0, with_shrink, true);
      }
    }
  }
}
#endif  // CKPD_BATCHED_TETRAHEDRA

struct BoundWorker {
  UpperFamily family;
  SlotSums sums;
  Rows rows;
#if defined(CKPD_BATCHED_TETRAHEDRA)
  // Per slot of the centre: its tetrahedra's terms in lanes, summed across the lanes once per
  // centre (add_centre) and cleared again.
  std::vector<lanes::TermLanes> slot_lanes, slot_lanes_triangles;
#endif
};

std::vector<BoundWorker>& bound_workers() {
  thread_local std::vector<BoundWorker> workers;
  return workers;
}

// Visits centre i's bonds, triangles and tetrahedra (upper family) and adds each vertex's terms
// to `rows`.
template <class Model>
void add_centre(const Model& model, const Body& body, std::size_t i, bool triangles,
                bool tetrahedra, bool with_shrink, BoundWorker& wk) {
  const UpperFamily& u = wk.family;
  SlotSums& sums = wk.sums;
  Rows& rows = wk.rows;
  const bool planar = body.dimension == 2;
  auto q1 = [&](std::size_t p) { return &rows.q1[6 * p]; };
  auto shrink_at = [&](std::size_t p, double measure, double rate) {
    if (with_shrink) shrink(measure, rate, rows.shrink[p]);
  };
  // Bonds: the tangent of C1 L e^2 / 2 in l, along the bond and across it ((I - n n^T) / l),
  // the same for both ends.
  for (std::size_t a = 0; a < u.n; ++a) {
    if (!u.bonded[a]) continue;
    const std::size_t j = u.index[a];
    const double L = u.L[a], l = u.l[a];
    if (!(l > 0)) {
      rows.collapsed[i] = rows.collapsed[j] = 1;
      continue;
    }
    const Vec3 nv = u.cur[a] / l;
    double slope, curvature;
    tangent(model, l / L, 0, slope, curvature);
    const double along = std::abs(curvature) * law_curvature(2.0, L),
                 across = 2.0 * std::abs(slope) / l;
    // along n n^T + across (I - n n^T), with the zz entry of (I - n n^T) left out in a plane.
    const double t[6] = {(along - across) * nv.x() * nv.x() + across,
                         (along - across) * nv.x() * nv.y(),
                         (along - across) * nv.x() * nv.z(),
                         (along - across) * nv.y() * nv.y() + across,
                         (along - across) * nv.y() * nv.z(),
                         (along - across) * nv.z() * nv.z() + (planar ? 0.0 : across)};
    for (const std::size_t p : {i, j}) {
      double* q = q1(p);
      for (int e = 0; e < 6; ++e) q[e] += t[e];
    }
    if (with_shrink) {
      const double rate = nv.dot(u.w(a));
      shrink_at(i, l, rate);
      shrink_at(j, l, rate);
    }
  }
  if (!triangles && !tetrahedra) return;
  sums.reset(u.stride + 1, with_shrink);
#if defined(CKPD_BATCHED_TETRAHEDRA)
  const bool in_lanes = sets_in_lanes;
  for (auto* slot_lanes : {&wk.slot_lanes, &wk.slot_lanes_triangles})
    if (slot_lanes->size() < u.n + 1) {
      lanes::TermLanes cleared;
      cleared.clear();
      slot_lanes->resize(u.n + 1, cleared);
    }
#else
  const bool in_lanes = false;
#endif
  for (std::size_t a = 0; a < u.n; ++a) {
    const std::uint64_t* row_a = &u.adjacent[a * u.words];
    if (triangles) {
#if defined(CKPD_BATCHED_TETRAHEDRA)
      if (in_lanes)
        add_triangles_lanes(model, body, u, a, with_shrink, sums, wk.slot_lanes_triangles.data());
#endif
      if (!in_lanes)
        for (std::size_t wb = (a + 1) / 64; wb < u.words; ++wb) {
          std::uint64_t bits = row_a[wb];
          if (wb == a / 64) bits &= (a % 64 == 63) ? 0 : (~std::uint64_t{0} << (a % 64 + 1));
          for (; bits; bits &= bits - 1)
            add_triangle_scalar(model, body, u, a,
                                wb * 64 + static_cast<std::size_t>(std::countr_zero(bits)),
                                with_shrink, sums);
        }
    }
    if (!tetrahedra) continue;
    for (std::size_t wb = (a + 1) / 64; wb < u.words; ++wb) {
      std::uint64_t bits = row_a[wb];
      if (wb == a / 64) bits &= (a % 64 == 63) ? 0 : (~std::uint64_t{0} << (a % 64 + 1));
      for (; bits; bits &= bits - 1) {
        const std::size_t b = wb * 64 + static_cast<std::size_t>(std::countr_zero(bits));
        const std::size_t ab = u.at(a, b);
        const bool ia = u.bonded[a], ib = u.bonded[b], eab = u.edge_intact(a, b);
        const PairOfSet pr{a, b, ab, ia, ib, eab};
#if defined(CKPD_BATCHED_TETRAHEDRA)
        if (in_lanes) {
          add_tetrahedra_lanes(model, body, u, pr, with_shrink, sums, wk.slot_lanes.data());
          continue;
        }
#endif
        add_tetrahedra_scalar(model, body, u, pr, with_shrink, sums);
      }
    }
  }
#if defined(CKPD_BATCHED_TETRAHEDRA)
  if (in_lanes)
    for (std::size_t s = 0; s <= u.n; ++s) {
      if (tetrahedra) {
        wk.slot_lanes[s].reduce_into(sums, s, with_shrink);
        wk.slot_lanes[s].clear();
      }
      if (triangles) {
        wk.slot_lanes_triangles[s].reduce_into(sums, s, with_shrink, true);
        wk.slot_lanes_triangles[s].clear();
      }
    }
#endif
  sums.flush(u, i, with_shrink, rows);
}

}  // namespace

void ckpd_current_stiffness_bound(const Body& body, std::vector<double>& bound,
                                  std::vector<double>* shrink_time) {
  const CkpdSethHillModel model = CkpdSethHillModel::of(body);
  const bool triangles = model.has_triangles() && body.has_pairs();
  const bool tetrahedra = model.has_tetrahedra() && body.has_triples();
  const bool with_shrink = shrink_time != nullptr;
  const std::size_t n = body.size();
  bound.assign(n, 0);
  if (shrink_time) shrink_time->assign(n, std::numeric_limits<double>::infinity());
  std::vector<BoundWorker>& workers = bound_workers();
  const std::size_t most = static_cast<std::size_t>(std::max(1, omp_get_max_threads()));
  if (workers.size() < most) workers.resize(most);
  int team = 1;
#pragma omp parallel
  {
#pragma omp single
    team = omp_get_num_threads();
    BoundWorker& wk = workers[static_cast<std::size_t>(omp_get_thread_num())];
    wk.rows.reset(n, with_shrink);
    // Static: which worker takes which centre depends on the thread count only.
#pragma omp for schedule(static, 64)
    for (std::size_t i = 0; i < n; ++i) {
      wk.family.load(body, i, triangles || tetrahedra, with_shrink);
      add_centre(model, body, i, triangles, tetrahedra, with_shrink, wk);
    }
    // Rows added in worker order, then each point's bound.
#pragma omp for schedule(static)
    for (std::size_t p = 0; p < n; ++p) {
      double q[3][6] = {};
      double iso2 = 0, iso3 = 0, t = std::numeric_limits<double>::infinity();
      bool collapsed = false;
      for (int s = 0; s < team; ++s) {
        const Rows& r = workers[static_cast<std::size_t>(s)].rows;
        for (int e = 0; e < 6; ++e) {
          q[0][e] += r.q1[6 * p + e];
          q[1][e] += r.q2[6 * p + e];
          q[2][e] += r.q3[6 * p + e];
        }
        iso2 += r.iso2[p];
        iso3 += r.iso3[p];
        collapsed = collapsed || r.collapsed[p];
        if (with_shrink) t = std::min(t, r.shrink[p]);
      }
      if (with_shrink) (*shrink_time)[p] = t;
      if (collapsed || !std::isfinite(iso2) || !std::isfinite(iso3)) {
        bound[p] = std::numeric_limits<double>::infinity();
        continue;
      }
      const std::array<double, 3> scale = body.force_form == ForceForm::energy_consistent
                                              ? conservative_bound_scale(body, p)
                                              : std::array<double, 3>{1, 1, 1};
      const double w[3] = {std::abs(body.constants.c1) * body.dv1[p] * scale[0],
                           std::abs(body.constants.c2) * body.dv2[p] * scale[1],
                           std::abs(body.constants.c3) * body.dv3[p] * scale[2]};
      double s[6];
      for (int e = 0; e < 6; ++e) s[e] = w[0] * q[0][e] + w[1] * q[1][e] + w[2] * q[2][e];
      Mat3 m;
      m << s[0], s[1], s[2], s[1], s[3], s[4], s[2], s[4], s[5];
      if (!m.allFinite()) {
        bound[p] = std::numeric_limits<double>::infinity();
        continue;
      }
      bound[p] =
          Eigen::SelfAdjointEigenSolver<Mat3>(m, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff() +
          w[1] * iso2 + w[2] * iso3;
    }
  }
}

void bond_shrink_time(const Body& body, std::vector<double>& shrink_time) {
  shrink_time.assign(body.size(), std::numeric_limits<double>::infinity());
#pragma omp parallel
  {
    FamilyScratch scratch;
    std::vector<Vec3> w;
#pragma omp for schedule(dynamic, 16)
    for (std::size_t i = 0; i < body.size(); ++i) {
      scratch.load(body, i, true, false);
      relative_velocities(body, i, scratch, w);
      double t = std::numeric_limits<double>::infinity();
      for (std::size_t a = 0; a < scratch.size(); ++a) {
        const double l = scratch.cur[a].norm();
        if (l > 0) shrink(l, scratch.cur[a].dot(w[a]) / l, t);
      }
      shrink_time[i] = t;
    }
  }
}

}  // namespace ckpd
