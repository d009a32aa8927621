// The CKPD stiffness bound at the current displacement, the plain path
// (reference/current_stiffness.hpp): every set of each point's family evaluated on its own from
// that point, every gradient norm and edge length taken where it is used. The optimised bound
// (bodies/current_stiffness.cpp) is tested against it.
#include "reference/current_stiffness.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
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

template <class Model>
double point_bound(const Model& model, const Body& body, std::size_t i, const FamilyScratch& s,
                   bool planar, const std::vector<Vec3>* w, double& shrink_time) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const double deg = body.degenerate_fraction;
  Mat3 q1 = Mat3::Zero(), q2 = Mat3::Zero(), q3 = Mat3::Zero();
  double iso2 = 0, iso3 = 0;  // the measures' own curvature, the same in every direction
  // Bonds: the tangent of C1 L e^2 / 2 in l, along the bond and across it ((I - n n^T) / l).
  for (std::size_t a = 0; a < s.size(); ++a) {
    const double L = s.length[a], l = s.cur[a].norm();
    if (!(l > 0)) return kInf;
    const double r = l / L;
    const Vec3 n = s.cur[a] / l;
    const Mat3 along = n * n.transpose();
    Mat3 across = Mat3::Identity() - along;
    if (planar) across(2, 2) = 0;  // a 2D body moves in its plane
    if (w) shrink(l, n.dot((*w)[a]), shrink_time);
    double slope, curvature;
    tangent(model, r, 0, slope, curvature);
    q1 += std::abs(curvature) * law_curvature(2.0, L) * along + 2.0 * std::abs(slope) / l * across;
  }
  if (model.has_triangles() && body.has_pairs()) {
    double s2[6] = {0, 0, 0, 0, 0, 0};  // q2's upper triangle: xx, xy, xz, yy, yz, zz
    s.for_each_pair([&](std::size_t a, std::size_t b) {
      const Vec3 P = s.ref[a], Q = s.ref[b];
      const Vec3 ref_area = P.cross(Q);
      const double A = ref_area.norm();
      if (A <= deg * s.length[a] * s.length[b]) return;
      const Vec3 p = s.cur[a], q = s.cur[b];
      const Vec3 area = p.cross(q);
      const double an = area.norm();
      if (!(an > 0)) {
        iso2 = kInf;
        return;
      }
      const double r = an / A;
      const bool inverted = model.triangle_inverted(area.z(), ref_area.z());
      const Vec3 unit = area / an;
      if (w) shrink(an, unit.dot((*w)[a].cross(q) + p.cross((*w)[b])), shrink_time);
      // grad_c |a| = G_c x n with G = (p - q, q, -p) (triangle_linearisation at the current
      // state); |grad_c a| is the length of the edge opposite c.
      const Vec3 g0 = (p - q).cross(unit), g1 = q.cross(unit), g2 = unit.cross(p);
      double slope, curvature;
      tangent(model, r, inverted ? model.pen2 : 0.0, slope, curvature);
      // add_bound(q2, ...) with g0's norm taken once and the symmetric upper triangle only.
      const double n0 = g0.norm();
      if (n0 > 0) {
        const double f =
            std::abs(curvature) * law_curvature(2.0, A) * (n0 + g1.norm() + g2.norm()) / n0;
        const Vec3 fg = f * g0;
        s2[0] += fg.x() * g0.x();
        s2[1] += fg.x() * g0.y();
        s2[2] += fg.x() * g0.z();
        s2[3] += fg.y() * g0.y();
        s2[4] += fg.y() * g0.z();
        s2[5] += fg.z() * g0.z();
      }
      const double e0 = (p - q).norm(), e1 = q.norm(), e2 = p.norm();
      const double out_of_plane = planar ? 0.0 : e0 * (e0 + e1 + e2) / an;
      iso2 += 2.0 * std::abs(slope) * (2.0 + out_of_plane);
    });
    q2 << s2[0], s2[1], s2[2], s2[1], s2[3], s2[4], s2[2], s2[4], s2[5];
  }
  if (model.has_tetrahedra() && body.has_triples()) {
    double s3[6] = {0, 0, 0, 0, 0, 0};  // q3's upper triangle: xx, xy, xz, yy, yz, zz
    s.for_each_triple([&](std::size_t a, std::size_t b, std::size_t c) {
      const Vec3 P = s.ref[a], Q = s.ref[b], R = s.ref[c];
      const double signed_V = P.dot(Q.cross(R)), V = std::abs(signed_V);
      if (V <= deg * s.length[a] * s.length[b] * s.length[c]) return;
      const Vec3 p = s.cur[a], q = s.cur[b], r = s.cur[c];
      const Vec3 gj = q.cross(r), gk = r.cross(p), gl = p.cross(q);
      const Vec3 gi = -(gj + gk + gl);
      const double v = p.dot(gj);
      if (v == 0) {
        iso3 = kInf;
        return;
      }
      const double ratio = std::abs(v) / V;
      if (w) {
        const double dv = (*w)[a].dot(gj) + (*w)[b].dot(gk) + (*w)[c].dot(gl);
        shrink(std::abs(v), v > 0 ? dv : -dv, shrink_time);
      }
      const bool inverted = model.tetrahedron_inverted(v, signed_V);
      double slope, curvature;
      tangent(model, ratio, inverted ? model.pen3 : 0.0, slope, curvature);
      // add_bound(q3, ...) with gi's norm taken once and the symmetric upper triangle only.
      const double ni = gi.norm();
      if (ni > 0) {
        const double f = std::abs(curvature) * law_curvature(6.0, V) *
                         (ni + gj.norm() + gk.norm() + gl.norm()) / ni;
        const Vec3 fg = f * gi;
        s3[0] += fg.x() * gi.x();
        s3[1] += fg.x() * gi.y();
        s3[2] += fg.x() * gi.z();
        s3[3] += fg.y() * gi.y();
        s3[4] += fg.y() * gi.z();
        s3[5] += fg.z() * gi.z();
      }
      // d2v / dx_i dx_d: the cross-product matrix of the edge opposite i and d.
      iso3 += 6.0 * std::abs(slope) * ((q - r).norm() + (r - p).norm() + (p - q).norm());
    });
    q3 << s3[0], s3[1], s3[2], s3[1], s3[3], s3[4], s3[2], s3[4], s3[5];
  }
  if (!std::isfinite(iso2) || !std::isfinite(iso3)) return kInf;
  const std::array<double, 3> scale = body.force_form == ForceForm::energy_consistent
                                          ? conservative_bound_scale(body, i)
                                          : std::array<double, 3>{1, 1, 1};
  const double w1 = std::abs(body.constants.c1) * body.dv1[i] * scale[0];
  const double w2 = std::abs(body.constants.c2) * body.dv2[i] * scale[1];
  const double w3 = std::abs(body.constants.c3) * body.dv3[i] * scale[2];
  const Mat3 q = w1 * q1 + w2 * q2 + w3 * q3;
  if (!q.allFinite()) return kInf;
  return Eigen::SelfAdjointEigenSolver<Mat3>(q, Eigen::EigenvaluesOnly).eigenvalues().maxCoeff() +
         w2 * iso2 + w3 * iso3;
}

}  // namespace

void reference_ckpd_current_stiffness_bound(const Body& body, std::vector<double>& bound,
                                            std::vector<double>* shrink_time) {
  const CkpdSethHillModel model = CkpdSethHillModel::of(body);
  const bool sets = body.has_pairs() || body.has_triples();
  const bool planar = body.dimension == 2;
  bound.assign(body.size(), 0);
  if (shrink_time) shrink_time->assign(body.size(), std::numeric_limits<double>::infinity());
#pragma omp parallel
  {
    FamilyScratch scratch;
    std::vector<Vec3> w;
#pragma omp for schedule(dynamic, 16)
    for (std::size_t i = 0; i < body.size(); ++i) {
      scratch.load(body, i, true, sets);
      double t = std::numeric_limits<double>::infinity();
      if (shrink_time) relative_velocities(body, i, scratch, w);
      bound[i] = point_bound(model, body, i, scratch, planar, shrink_time ? &w : nullptr, t);
      if (shrink_time) (*shrink_time)[i] = t;
    }
  }
}

}  // namespace ckpd
