#pragma once
// One point's interaction census: its ordered, non-degenerate two- and three-neighbour counts
// and the matrices of its stiffness bound (MODEL.md section 1; stable_step in body.hpp). The
// bound comes from each set's linearisation at the reference state (the model's
// *_linearisation): for a set with measure gradients g_c and curvature kappa, the contribution to
// point i is kappa (sum_c |g_c|) |g_i| g^_i g^_i^T, a directional Gershgorin bound.
#include <Eigen/Core>
#include <cmath>
#include <cstdint>

#include "bodies/family_scratch.hpp"
#include "bodies/set_law.hpp"

namespace ckpd {

struct PointCensus {
  std::uint32_t n2 = 0, n3 = 0;
  // Per unit C dV of each family.
  Eigen::Matrix3d q1 = Eigen::Matrix3d::Zero(), q2 = Eigen::Matrix3d::Zero(),
                  q3 = Eigen::Matrix3d::Zero();
};

// Adds weight (sum_c |g_c|) / |g_i| g_i g_i^T: the bound's term of one interaction at point i.
inline void add_bound(Eigen::Matrix3d& q, double weight, const Vec3& gi, double sum_norms) {
  const double n = gi.norm();
  if (n > 0) q += weight * sum_norms / n * (gi * gi.transpose());
}

template <class Model>
PointCensus census_point_of(const Model& model, const FamilyScratch& s, double degenerate) {
  PointCensus c;
  // Bonds: gradients -n and n of unit norm, curvature 1/L per unit C1.
  for (std::size_t a = 0; a < s.size(); ++a) {
    const Vec3 n = s.ref[a] / s.length[a];
    c.q1 += law_curvature(2.0, s.length[a]) * (n * n.transpose());
  }
  if constexpr (Model::kTriangles) {
    if (model.has_triangles()) {
      s.for_each_pair([&](std::size_t a, std::size_t b) {
        const Vec3 p = s.ref[a], q = s.ref[b];
        const double A = p.cross(q).norm();
        if (A <= degenerate * s.length[a] * s.length[b]) return;
        c.n2 += 2;
        const SetLinearisation<3> lin = model.triangle_linearisation(p, q);
        const Vec3* g = lin.gradient.data();
        add_bound(c.q2, lin.curvature(2.0), g[0], g[0].norm() + g[1].norm() + g[2].norm());
      });
    }
  }
  if constexpr (Model::kTetrahedra) {
    if (model.has_tetrahedra()) {
      s.for_each_triple([&](std::size_t a, std::size_t b, std::size_t d) {
        const Vec3 p = s.ref[a], q = s.ref[b], r = s.ref[d];
        const double V = std::abs(p.dot(q.cross(r)));
        if (V <= degenerate * s.length[a] * s.length[b] * s.length[d]) return;
        c.n3 += 6;
        const SetLinearisation<4> lin = model.tetrahedron_linearisation(p, q, r);
        const Vec3* g = lin.gradient.data();
        add_bound(c.q3, lin.curvature(6.0), g[0],
                  g[0].norm() + g[1].norm() + g[2].norm() + g[3].norm());
      });
    }
  }
  return c;
}

}  // namespace ckpd
