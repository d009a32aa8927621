// The CKPD stiffness bound at the current displacement (current_stiffness.hpp).
//
// What it shares, and why it is cheap enough to run after every step: the quantities of a set
// that depend on one pair of its vertices only are computed once per pair of the family and
// kept in a pair table (PairTable): the current and reference cross products of the two
// offsets (a triangle's area vector; a tetrahedron's three face gradients q x r, r x p, p x q),
// their norms and the distance between the two members (an edge). A tetrahedron then costs one
// square root (the norm of the centre's gradient) where the set-by-set evaluation
// (reference/current_stiffness.cpp, tested against this file) took seven and three cross
// products; a triangle's gradient norms are edge lengths (grad_c |a| = G_c x n with n normal to
// the plane of G_c), so it takes one square root where the plain path took seven.
#include "bodies/current_stiffness.hpp"

#include <omp.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#include "bodies/census.hpp"
#include "bodies/ckpd_model.hpp"
#include "bodies/family_scratch.hpp"

namespace ckpd {

namespace {

using Mat3 = Eigen::Matrix3d;

// model.tangent_at with closed forms for the measures in use with m <= 0 (m = 0: one log;
// m = -1/2: rational), the same values to rounding: the transcendental functions of the
// general form (log1p, expm1, exp per set) were a fifth of the bound's time.
template <class Model>
inline void tangent(const Model& model, double r, double penalty, double& slope,
                    double& curvature) {
  if constexpr (std::is_same_v<Model, CkpdSethHillModel>) {
    const double m = model.strain.m;
    if (m == 0) {
      const double e = std::log(r), ir = 1 / r;  // e_0 = log r, r^(2m - 1) = 1 / r
      slope = e * ir + penalty;
      curvature = (1 - e) * ir * ir;
      return;
    }
    if (m == -0.5) {
      const double ir = 1 / r, e = 1 - ir, g = ir * ir;  // e = 1 - 1/r, r^(2m - 1) = r^-2
      slope = e * g + penalty;
      curvature = g * g - 2 * e * g * ir;
      return;
    }
  }
  model.tangent_at(r, penalty, slope, curvature);
}

// The time a measure m of a set (or bond) takes to reach zero at its rate dm/dt when shrinking.
inline void shrink(double measure, double rate, double& time) {
  if (rate < 0) time = std::min(time, measure / -rate);
}

// w[a]: the velocity of slot a's point relative to point i's.
void relative_velocities(const Body& body, std::size_t i, const FamilyScratch& s,
                         std::vector<Vec3>& w) {
  w.resize(s.size());
  for (std::size_t a = 0; a < s.size(); ++a) w[a] = body.velocity[s.index[a]] - body.velocity[i];
}

// The pair table of one point's family: for slots a < b adjacent in the scratch, at a * n + b,
// the current cross product p_a x p_b and its norm, the reference one's norm and vector, and
// the current distance |p_a - p_b|. Grows only.
struct PairTable {
  std::vector<double> cx, cy, cz, cn, rx, ry, rz, rn, edge;
  std::size_t n = 0;
  void size_for(std::size_t slots, bool reference_vector) {
    n = slots;
    const std::size_t need = slots * slots;
    for (std::vector<double>* v : {&cx, &cy, &cz, &cn, &edge, &rn})
      if (v->size() < need) v->resize(need);
    if (reference_vector)
      for (std::vector<double>* v : {&rx, &ry, &rz})
        if (v->size() < need) v->resize(need);
  }
  std::size_t at(std::size_t a, std::size_t b) const { return a * n + b; }
  Vec3 cur(std::size_t k) const { return {cx[k], cy[k], cz[k]}; }
  Vec3 ref(std::size_t k) const { return {rx[k], ry[k], rz[k]}; }
};

// One worker's buffers, kept by the calling thread between calls (no allocation in a step once
// grown): by omp_get_thread_num(), not thread_local in the workers (bond_failure.hpp says why).
struct BoundWorker {
  FamilyScratch scratch;
  PairTable pairs;
  std::vector<double> l;  // current bond lengths by slot
  std::vector<Vec3> w;    // relative velocities by slot
};

void fill_pairs(const FamilyScratch& s, PairTable& t, bool reference_vector) {
  t.size_for(s.size(), reference_vector);
  s.for_each_pair([&](std::size_t a, std::size_t b) {
    const std::size_t k = t.at(a, b);
    const Vec3 c = s.cur[a].cross(s.cur[b]), R = s.ref[a].cross(s.ref[b]);
    t.cx[k] = c.x();
    t.cy[k] = c.y();
    t.cz[k] = c.z();
    t.cn[k] = c.norm();
    t.rn[k] = R.norm();
    if (reference_vector) {
      t.rx[k] = R.x();
      t.ry[k] = R.y();
      t.rz[k] = R.z();
    }
    t.edge[k] = (s.cur[a] - s.cur[b]).norm();
  });
}

// Adds f g g^T to the upper triangle q (xx, xy, xz, yy, yz, zz).
inline void add_dyad(double (&q)[6], double f, const Vec3& g) {
  const Vec3 fg = f * g;
  q[0] += fg.x() * g.x();
  q[1] += fg.x() * g.y();
  q[2] += fg.x() * g.z();
  q[3] += fg.y() * g.y();
  q[4] += fg.y() * g.z();
  q[5] += fg.z() * g.z();
}

inline Mat3 from_upper(const double (&q)[6]) {
  Mat3 m;
  m << q[0], q[1], q[2], q[1], q[3], q[4], q[2], q[4], q[5];
  return m;
}

template <class Model>
double point_bound(const Model& model, const Body& body, std::size_t i, BoundWorker& wk,
                   bool planar, bool with_shrink, double& shrink_time) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const FamilyScratch& s = wk.scratch;
  const PairTable& t = wk.pairs;
  const std::vector<Vec3>& w = wk.w;
  const double deg = body.degenerate_fraction;
  Mat3 q1 = Mat3::Zero();
  double iso2 = 0, iso3 = 0;  // the measures' own curvature, the same in every direction
  // Bonds: the tangent of C1 L e^2 / 2 in l, along the bond and across it ((I - n n^T) / l).
  wk.l.resize(s.size());
  for (std::size_t a = 0; a < s.size(); ++a) {
    const double L = s.length[a], l = s.cur[a].norm();
    wk.l[a] = l;
    if (!(l > 0)) return kInf;
    const double r = l / L;
    const Vec3 n = s.cur[a] / l;
    const Mat3 along = n * n.transpose();
    Mat3 across = Mat3::Identity() - along;
    if (planar) across(2, 2) = 0;  // a 2D body moves in its plane
    if (with_shrink) shrink(l, n.dot(w[a]), shrink_time);
    double slope, curvature;
    tangent(model, r, 0, slope, curvature);
    q1 += std::abs(curvature) * law_curvature(2.0, L) * along + 2.0 * std::abs(slope) / l * across;
  }
  const double* l = wk.l.data();
  double s2[6] = {0, 0, 0, 0, 0, 0}, s3[6] = {0, 0, 0, 0, 0, 0};
  if (model.has_triangles() && body.has_pairs()) {
    s.for_each_pair([&](std::size_t a, std::size_t b) {
      const std::size_t k = t.at(a, b);
      const double A = t.rn[k];
      if (A <= deg * s.length[a] * s.length[b]) return;
      const double an = t.cn[k];
      if (!(an > 0)) {
        iso2 = kInf;
        return;
      }
      const Vec3& p = s.cur[a];
      const Vec3& q = s.cur[b];
      const Vec3 area = t.cur(k);
      const double r = an / A;
      const bool inverted = model.triangle_inverted(
          area.z(), s.ref[a].x() * s.ref[b].y() - s.ref[a].y() * s.ref[b].x());
      const Vec3 unit = area / an;
      if (with_shrink) shrink(an, unit.dot(w[a].cross(q) + p.cross(w[b])), shrink_time);
      // grad_c |a| = G_c x n with G = (p - q, q, -p); n is normal to every G_c, so |grad_c a|
      // is the length of the edge G_c: e0 = |p - q| for the centre, |q| and |p| for a and b.
      const double e0 = t.edge[k], e1 = l[b], e2 = l[a];
      double slope, curvature;
      tangent(model, r, inverted ? model.pen2 : 0.0, slope, curvature);
      if (e0 > 0) {
        const Vec3 g0 = (p - q).cross(unit);
        add_dyad(s2, std::abs(curvature) * law_curvature(2.0, A) * (e0 + e1 + e2) / e0, g0);
      }
      const double out_of_plane = planar ? 0.0 : e0 * (e0 + e1 + e2) / an;
      iso2 += 2.0 * std::abs(slope) * (2.0 + out_of_plane);
    });
  }
  if (model.has_tetrahedra() && body.has_triples()) {
    s.for_each_triple([&](std::size_t a, std::size_t b, std::size_t c) {
      const std::size_t ab = t.at(a, b), ac = t.at(a, c), bc = t.at(b, c);
      const Vec3& P = s.ref[a];
      const double signed_V = P.dot(t.ref(bc)), V = std::abs(signed_V);
      if (V <= deg * s.length[a] * s.length[b] * s.length[c]) return;
      const Vec3& p = s.cur[a];
      // The face gradients: q x r, r x p = -(p x r), p x q.
      const Vec3 gj = t.cur(bc), gk = -t.cur(ac), gl = t.cur(ab);
      const Vec3 gi = -(gj + gk + gl);
      const double v = p.dot(gj);
      if (v == 0) {
        iso3 = kInf;
        return;
      }
      const double ratio = std::abs(v) / V;
      if (with_shrink) {
        const double dv = w[a].dot(gj) + w[b].dot(gk) + w[c].dot(gl);
        shrink(std::abs(v), v > 0 ? dv : -dv, shrink_time);
      }
      const bool inverted = model.tetrahedron_inverted(v, signed_V);
      double slope, curvature;
      tangent(model, ratio, inverted ? model.pen3 : 0.0, slope, curvature);
      const double ni = gi.norm();
      if (ni > 0)
        add_dyad(s3,
                 std::abs(curvature) * law_curvature(6.0, V) *
                     (ni + t.cn[bc] + t.cn[ac] + t.cn[ab]) / ni,
                 gi);
      // d2v / dx_i dx_d: the cross-product matrix of the edge opposite i and d.
      iso3 += 6.0 * std::abs(slope) * (t.edge[bc] + t.edge[ac] + t.edge[ab]);
    });
  }
  if (!std::isfinite(iso2) || !std::isfinite(iso3)) return kInf;
  const std::array<double, 3> scale = body.force_form == ForceForm::energy_consistent
                                          ? conservative_bound_scale(body, i)
                                          : std::array<double, 3>{1, 1, 1};
  const double w1 = std::abs(body.constants.c1) * body.dv1[i] * scale[0];
  const double w2 = std::abs(body.constants.c2) * body.dv2[i] * scale[1];
  const double w3 = std::abs(body.constants.c3) * body.dv3[i] * scale[2];
  const Mat3 q = w1 * q1 + w2 * from_upper(s2) + w3 * from_upper(s3);
  if (!q.allFinite()) return kInf;
  return Eigen::SelfAdjointEigenSolver<Mat3>(q, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff() +
         w2 * iso2 + w3 * iso3;
}

std::vector<BoundWorker>& bound_workers() {
  thread_local std::vector<BoundWorker> workers;
  return workers;
}

}  // namespace

void ckpd_current_stiffness_bound(const Body& body, std::vector<double>& bound,
                                  std::vector<double>* shrink_time) {
  const CkpdSethHillModel model = CkpdSethHillModel::of(body);
  const bool triangles = model.has_triangles() && body.has_pairs();
  const bool tetrahedra = model.has_tetrahedra() && body.has_triples();
  const bool planar = body.dimension == 2;
  bound.assign(body.size(), 0);
  if (shrink_time) shrink_time->assign(body.size(), std::numeric_limits<double>::infinity());
  std::vector<BoundWorker>& workers = bound_workers();
  const std::size_t team = static_cast<std::size_t>(std::max(1, omp_get_max_threads()));
  if (workers.size() < team) workers.resize(team);
#pragma omp parallel
  {
    BoundWorker& wk = workers[static_cast<std::size_t>(omp_get_thread_num())];
#pragma omp for schedule(dynamic, 16)
    for (std::size_t i = 0; i < body.size(); ++i) {
      wk.scratch.load(body, i, true, triangles || tetrahedra);
      if (triangles || tetrahedra) fill_pairs(wk.scratch, wk.pairs, tetrahedra);
      double t = std::numeric_limits<double>::infinity();
      if (shrink_time) relative_velocities(body, i, wk.scratch, wk.w);
      bound[i] = point_bound(model, body, i, wk, planar, shrink_time != nullptr, t);
      if (shrink_time) (*shrink_time)[i] = t;
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
