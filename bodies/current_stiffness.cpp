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
// G_c). Each worker sums into its own rows, added in worker order: deterministic per thread count.
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

// The centre's upper family: its members with a higher index, bonded or not (a failed bond of
// the centre still leaves the set to the vertices whose own bonds hold, under centre_bonds), and
// for adjacent slots a < b (members within a horizon of each other) the pair quantities at
// a * n + b. Grows only.
struct UpperFamily {
  std::size_t n = 0, words = 0;
  std::vector<std::uint32_t> index;
  std::vector<Vec3> ref, cur, w;     // offsets from the centre; velocities relative to it
  std::vector<double> L, l;          // reference and current lengths
  std::vector<std::uint8_t> bonded;  // the centre's bond to the slot is intact
  std::vector<std::uint64_t> adjacent;
  // Per adjacent pair: current cross product p_a x p_b and norm, reference cross product and
  // norm, current and reference distance, whether the members' own bond is intact.
  std::vector<Vec3> cross, ref_cross;
  std::vector<double> cross_norm, ref_cross_norm, edge, ref_edge;
  std::vector<std::uint8_t> edge_intact;

  std::size_t at(std::size_t a, std::size_t b) const { return a * n + b; }
  bool adj(std::size_t a, std::size_t b) const {
    return (adjacent[a * words + b / 64] >> (b % 64)) & 1;
  }

  void load(const Body& body, std::size_t i, bool sets, bool with_velocity) {
    const std::size_t begin = body.family.offset[i], end = body.family.offset[i + 1];
    const Vec3 Xi = body.reference_position[i];
    const bool has_u = !body.displacement.empty();
    const Vec3 ui = has_u ? body.displacement[i] : Vec3::Zero();
    n = 0;
    const std::size_t most = end - begin;
    for (auto* v : {&ref, &cur, &w})
      if (v->size() < most) v->resize(most);
    if (index.size() < most) {
      index.resize(most);
      L.resize(most);
      l.resize(most);
      bonded.resize(most);
    }
    for (std::size_t k = begin; k < end; ++k) {
      const std::uint32_t j = body.family.neighbour[k];
      if (j <= i) continue;
      index[n] = j;
      ref[n] = body.reference_position[j] - Xi;
      cur[n] = has_u ? Vec3(ref[n] + (body.displacement[j] - ui)) : ref[n];
      if (with_velocity) w[n] = body.velocity[j] - body.velocity[i];
      L[n] = ref[n].norm();
      l[n] = cur[n].norm();
      bonded[n] = body.bond_intact[k];
      ++n;
    }
    if (!sets) return;
    words = (n + 63) / 64;
    if (adjacent.size() < n * words) adjacent.resize(n * words);
    std::fill(adjacent.begin(), adjacent.begin() + static_cast<std::ptrdiff_t>(n * words), 0);
    const std::size_t pairs = n * n;
    if (cross.size() < pairs) {
      cross.resize(pairs);
      ref_cross.resize(pairs);
      cross_norm.resize(pairs);
      ref_cross_norm.resize(pairs);
      edge.resize(pairs);
      ref_edge.resize(pairs);
      edge_intact.resize(pairs);
    }
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
        adjacent[a * words + b / 64] |= std::uint64_t{1} << (b % 64);
        edge_intact[k] =
            body.bond_intact[static_cast<std::size_t>(it - body.family.neighbour.data())];
        cross[k] = cur[a].cross(cur[b]);
        cross_norm[k] = cross[k].norm();
        ref_cross[k] = ref[a].cross(ref[b]);
        ref_cross_norm[k] = ref_cross[k].norm();
        edge[k] = (cur[a] - cur[b]).norm();
        ref_edge[k] = d.norm();
      }
    }
  }
};

// One centre's triangle and tetrahedron terms per vertex slot (0: the centre, 1 + a: upper slot
// a), added to the worker's rows once per centre (flush): a set's vertex terms land in a few
// contiguous slot rows instead of scattered rows of the whole body. Measured on half-resolution
// Kalthoff-Winkler at m = -1/2: 4-13 % off the bound's time (docs/PERFORMANCE.md); most of the
// bound is arithmetic, not these adds. The sums per point change only in their association.
struct SlotSums {
  std::vector<double> q2, q3, iso2, iso3, shrink;
  std::vector<std::uint8_t> collapsed;
  void reset(std::size_t slots, bool with_shrink) {
    q2.assign(6 * slots, 0.0);
    q3.assign(6 * slots, 0.0);
    iso2.assign(slots, 0.0);
    iso3.assign(slots, 0.0);
    if (with_shrink) shrink.assign(slots, std::numeric_limits<double>::infinity());
    collapsed.assign(slots, 0);
  }
  void flush(const UpperFamily& u, std::size_t i, bool with_shrink, Rows& rows) const {
    for (std::size_t s = 0; s <= u.n; ++s) {
      const std::size_t p = s == 0 ? i : u.index[s - 1];
      for (int e = 0; e < 6; ++e) {
        rows.q2[6 * p + e] += q2[6 * s + e];
        rows.q3[6 * p + e] += q3[6 * s + e];
      }
      rows.iso2[p] += iso2[s];
      rows.iso3[p] += iso3[s];
      if (with_shrink) rows.shrink[p] = std::min(rows.shrink[p], shrink[s]);
      rows.collapsed[p] |= collapsed[s];
    }
  }
};

struct BoundWorker {
  UpperFamily family;
  SlotSums sums;
  Rows rows;
};

std::vector<BoundWorker>& bound_workers() {
  thread_local std::vector<BoundWorker> workers;
  return workers;
}

// Visits centre i's bonds, triangles and tetrahedra (upper family) and adds each vertex's terms
// to `rows`.
template <class Model>
void add_centre(const Model& model, const Body& body, std::size_t i, const UpperFamily& u,
                bool triangles, bool tetrahedra, bool with_shrink, SlotSums& sums, Rows& rows) {
  const bool planar = body.dimension == 2;
  const bool all_edges = body.damage_rule == DamageRule::all_edges;
  const double deg = body.degenerate_fraction;
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
      const double rate = nv.dot(u.w[a]);
      shrink_at(i, l, rate);
      shrink_at(j, l, rate);
    }
  }
  if (!triangles && !tetrahedra) return;
  sums.reset(u.n + 1, with_shrink);
  auto shrink_slot = [&](std::size_t slot, double measure, double rate) {
    if (with_shrink) shrink(measure, rate, sums.shrink[slot]);
  };
  for (std::size_t a = 0; a < u.n; ++a) {
    const std::uint64_t* row_a = &u.adjacent[a * u.words];
    for (std::size_t wb = (a + 1) / 64; wb < u.words; ++wb) {
      std::uint64_t bits = row_a[wb];
      if (wb == a / 64) bits &= (a % 64 == 63) ? 0 : (~std::uint64_t{0} << (a % 64 + 1));
      for (; bits; bits &= bits - 1) {
        const std::size_t b = wb * 64 + static_cast<std::size_t>(std::countr_zero(bits));
        const std::size_t ab = u.at(a, b);
        const bool ia = u.bonded[a], ib = u.bonded[b], eab = u.edge_intact[ab];
        if (triangles) {
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
          if (act[0] || act[1] || act[2]) {
            const std::size_t slot[3] = {0, 1 + a, 1 + b};
            const double an = u.cross_norm[ab];
            if (!(an > 0)) {
              for (int v = 0; v < 3; ++v)
                if (act[v]) sums.collapsed[slot[v]] = 1;
            } else {
              const Vec3& p = u.cur[a];
              const Vec3& q = u.cur[b];
              const Vec3& area = u.cross[ab];
              const bool inverted = model.triangle_inverted(area.z(), u.ref_cross[ab].z());
              const Vec3 unit = area / an;
              double slope, curvature;
              tangent(model, an / A, inverted ? model.pen2 : 0.0, slope, curvature);
              // grad |a| at i, a, b: (p - q) x n, q x n, n x p; their norms are the edges
              // opposite each vertex.
              const double e[3] = {u.edge[ab], u.l[b], u.l[a]};
              const double sum = e[0] + e[1] + e[2];
              const double c = std::abs(curvature) * law_curvature(2.0, A) * sum;
              const Vec3 g[3] = {(p - q).cross(unit), q.cross(unit), unit.cross(p)};
              const double rate = with_shrink ? unit.dot(u.w[a].cross(q) + p.cross(u.w[b])) : 0.0;
              for (int v = 0; v < 3; ++v) {
                if (!act[v]) continue;
                const std::size_t sv = slot[v];
                if (e[v] > 0) add_dyad(&sums.q2[6 * sv], c / e[v], g[v]);
                const double out_of_plane = planar ? 0.0 : e[v] * sum / an;
                sums.iso2[sv] += 2.0 * std::abs(slope) * (2.0 + out_of_plane);
                shrink_slot(sv, an, rate);
              }
            }
          }
        }
        if (!tetrahedra) continue;
        const std::uint64_t* row_b = &u.adjacent[b * u.words];
        for (std::size_t wc = (b + 1) / 64; wc < u.words; ++wc) {
          std::uint64_t cbits = row_a[wc] & row_b[wc];
          if (wc == b / 64) cbits &= (b % 64 == 63) ? 0 : (~std::uint64_t{0} << (b % 64 + 1));
          for (; cbits; cbits &= cbits - 1) {
            const std::size_t c = wc * 64 + static_cast<std::size_t>(std::countr_zero(cbits));
            const std::size_t ac = u.at(a, c), bc = u.at(b, c);
            const bool ic = u.bonded[c], eac = u.edge_intact[ac], ebc = u.edge_intact[bc];
            const bool every = ia && ib && ic && eab && eac && ebc;
            bool act[4] = {all_edges ? every : ia && ib && ic, all_edges ? every : ia && eab && eac,
                           all_edges ? every : ib && eab && ebc,
                           all_edges ? every : ic && eac && ebc};
            const double signed_V = u.ref[a].dot(u.ref_cross[bc]), V = std::abs(signed_V);
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
            const Vec3 gj = u.cross[bc], gk = -u.cross[ac], gl = u.cross[ab];
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
            const double norm[4] = {gi.norm(), u.cross_norm[bc], u.cross_norm[ac],
                                    u.cross_norm[ab]};
            const double sum = norm[0] + norm[1] + norm[2] + norm[3];
            const double cc = std::abs(curvature) * law_curvature(6.0, V) * sum;
            const Vec3* g[4] = {&gi, &gj, &gk, &gl};
            // d2v / dx_x dx_d: the cross-product matrix of the edge opposite x and d; summed over
            // d, the three edges of the face opposite x.
            const double eab_ = u.edge[ab], eac_ = u.edge[ac], ebc_ = u.edge[bc];
            const double face[4] = {eab_ + eac_ + ebc_, u.l[b] + u.l[c] + ebc_,
                                    u.l[a] + u.l[c] + eac_, u.l[a] + u.l[b] + eab_};
            double rate = 0;
            if (with_shrink) {
              const double dv = u.w[a].dot(gj) + u.w[b].dot(gk) + u.w[c].dot(gl);
              rate = v > 0 ? dv : -dv;
            }
            const double s6 = 6.0 * std::abs(slope);
            for (int x = 0; x < 4; ++x) {
              if (!act[x]) continue;
              const std::size_t sx = slot[x];
              if (norm[x] > 0) add_dyad(&sums.q3[6 * sx], cc / norm[x], *g[x]);
              sums.iso3[sx] += s6 * face[x];
              shrink_slot(sx, std::abs(v), rate);
            }
          }
        }
      }
    }
  }
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
      add_centre(model, body, i, wk.family, triangles, tetrahedra, with_shrink, wk.sums, wk.rows);
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
