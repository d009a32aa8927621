#pragma once
// One point's interaction census: its ordered, non-degenerate two- and three-neighbour counts
// and the matrices of its stiffness bound (MODEL.md section 1; stable_step in body.hpp). The
// bound comes from each set's linearisation at the reference state (the model's
// *_linearisation): for a set with measure gradients g_c and curvature kappa, the contribution to
// point i is kappa (sum_c |g_c|) |g_i| g^_i g^_i^T, a directional Gershgorin bound.
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <vector>

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

// Bonds and triangles, set by set (O(m^4) at most; the tetrahedra are O(m^6)).
template <class Model>
void add_bond_and_triangle_bounds(const Model& model, const FamilyScratch& s, double degenerate,
                                  PointCensus& c) {
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
}

// The tetrahedra set by set: each one's linearisation from the model. Any model.
template <class Model>
void add_tetrahedron_bounds_by_set(const Model& model, const FamilyScratch& s, double degenerate,
                                   PointCensus& c) {
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

// The whole census set by set: the reference for the vector loop below.
template <class Model>
PointCensus census_point_by_set(const Model& model, const FamilyScratch& s, double degenerate) {
  PointCensus c;
  add_bond_and_triangle_bounds(model, s, degenerate, c);
  if constexpr (Model::kTetrahedra) {
    if (model.has_tetrahedra()) add_tetrahedron_bounds_by_set(model, s, degenerate, c);
  }
  return c;
}

// The tetrahedra's terms for the volume measure |v| (CkpdLaw's tetrahedron_linearisation: the
// gradients s (q x r, r x p, p x q) at the neighbours, minus their sum at the centre, curvature
// 6 / V per unit C dV), a pair (a, b) at a time, vectorised over its thirds c: the tetrahedra
// are O(m^6) per family and the set-by-set loop made most of a small body's set-up time (a
// census per distinct family: near surfaces almost every point). The sign s drops out of
// g g^T and of the norms. The same sets as the set-by-set loop (the same degenerate test,
// multiplied in the same order) and the same terms, summed in another order: equal to
// round-off (tests/test_census.cpp).
inline void add_volume_tetrahedron_bounds(const FamilyScratch& s, double degenerate,
                                          PointCensus& c) {
  const std::size_t n = s.size();
  std::vector<std::uint32_t> thirds(n);
  // The thirds' offsets and lengths, copied contiguous for the vector loop (no gathers).
  std::vector<double> x(n), y(n), z(n), length(n);
  std::uint32_t n3 = 0;
  double xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;
  s.for_each_pair_with_thirds(thirds.data(), [&](std::size_t a, std::size_t b,
                                                 const std::uint32_t* third, std::size_t m) {
    const double px = s.ref[a].x(), py = s.ref[a].y(), pz = s.ref[a].z();
    const double qx = s.ref[b].x(), qy = s.ref[b].y(), qz = s.ref[b].z();
    for (std::size_t k = 0; k < m; ++k) {
      const Vec3& r = s.ref[third[k]];
      x[k] = r.x();
      y[k] = r.y();
      z[k] = r.z();
      length[k] = s.length[third[k]];
    }
    // p x q, the gradient at c's vertex, and its norm: the same for every third.
    const double lx = py * qz - pz * qy, ly = pz * qx - px * qz, lz = px * qy - py * qx;
    const double l_norm = std::sqrt(lx * lx + ly * ly + lz * lz);
    const double pair_limit = degenerate * s.length[a] * s.length[b];
    std::uint32_t live = 0;
    double sxx = 0, sxy = 0, sxz = 0, syy = 0, syz = 0, szz = 0;
#pragma omp simd reduction(+ : live, sxx, sxy, sxz, syy, syz, szz)
    for (std::size_t k = 0; k < m; ++k) {
      const double rx = x[k], ry = y[k], rz = z[k];
      const double jx = qy * rz - qz * ry, jy = qz * rx - qx * rz, jz = qx * ry - qy * rx;  // q x r
      const double kx = ry * pz - rz * py, ky = rz * px - rx * pz, kz = rx * py - ry * px;  // r x p
      const double V = std::abs(px * jx + py * jy + pz * jz);
      const double gx = jx + kx + lx, gy = jy + ky + ly, gz = jz + kz + lz;  // minus the centre's
      const double g_norm = std::sqrt(gx * gx + gy * gy + gz * gz);
      const double norms = g_norm + std::sqrt(jx * jx + jy * jy + jz * jz) +
                           std::sqrt(kx * kx + ky * ky + kz * kz) + l_norm;
      const bool set = V > pair_limit * length[k];
      // add_bound's weight: (6 / V) (sum of the norms) / |g|, none where |g| = 0.
      const bool term = set && g_norm > 0;
      const double w = term ? 6 * norms / (term ? V * g_norm : 1.0) : 0.0;
      live += set ? 6u : 0u;
      sxx += w * gx * gx;
      sxy += w * gx * gy;
      sxz += w * gx * gz;
      syy += w * gy * gy;
      syz += w * gy * gz;
      szz += w * gz * gz;
    }
    n3 += live;
    xx += sxx;
    xy += sxy;
    xz += sxz;
    yy += syy;
    yz += syz;
    zz += szz;
  });
  c.n3 += n3;
  c.q3 += (Eigen::Matrix3d() << xx, xy, xz, xy, yy, yz, xz, yz, zz).finished();
}

// One point's census: bonds and triangles set by set, the tetrahedra in the vector loop for a
// model whose tetrahedron measure is the volume (Model::kVolumeTetrahedra), else set by set.
template <class Model>
PointCensus census_point_of(const Model& model, const FamilyScratch& s, double degenerate) {
  PointCensus c;
  add_bond_and_triangle_bounds(model, s, degenerate, c);
  if constexpr (Model::kTetrahedra) {
    if (model.has_tetrahedra()) {
      if constexpr (requires { requires Model::kVolumeTetrahedra; })
        add_volume_tetrahedron_bounds(s, degenerate, c);
      else
        add_tetrahedron_bounds_by_set(model, s, degenerate, c);
    }
  }
  return c;
}

}  // namespace ckpd
