#pragma once
// The neighbourhood that takes up a frictional contact's couple at a deformable point
// (docs/CONTACT_LAWS.md, "Angular momentum between deformable points").
//
// A deformable point has no spin: a tangential force F acting at the contact point p, applied at
// x^i, leaves out the couple T = (p - x^i) x F that a force at p exerts about x^i. The cluster
// K^i = {i} and its intact bond partners, with masses m_k = rho V^k, takes it up as rigid-body
// statics would: with rho_k = x^k - c measured from the cluster's centre of mass c,
//
//   J = sum m_k (|rho_k|^2 I - rho_k rho_k^T),     mu = J^+ T,     g_k = m_k mu x rho_k,
//
// the set of forces of least kinetic norm sum |g_k|^2 / m_k with sum g_k = 0 (so linear momentum
// is untouched) and sum rho_k x g_k = J mu = T (the couple), since sum m_k rho_k = 0. Its power
// is sum g_k . v^k = mu . L = T . omega with L = sum m_k rho_k x v^k and omega = J^+ L, the
// cluster's mean spin: a contact that moves its end with v^i + omega x (p - x^i) (cluster_spin)
// books every force's work, as for a rigid body's spin. J^+ is the pseudo-inverse: a cluster
// whose points are collinear (a point with one intact bond, in 3D) takes no couple about that
// line; a point without intact bonds none at all (it has no neighbourhood to hand it to). In 2D
// (the plane z = 0) only the z components exist, J_zz = sum m_k |rho_k|^2.
#include <Eigen/Eigenvalues>
#include <cstdint>

#include "contact/point_set.hpp"

namespace ckpd {

// Whether a point of this view can have a cluster: a deformable body with its bond families.
inline bool has_clusters(const PointSet& body) {
  return !body.spins && !body.family_offset.empty();
}

namespace detail {

// The cluster of point i, positions taken relative to x^i (its small extent keeps its digits):
// mass, centre offset c - x^i and J about c.
struct ClusterGeometry {
  double mass = 0;
  Vec3 centre = Vec3::Zero();  // c - x^i
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
};

template <typename Visit>
void for_cluster(const PointSet& body, std::uint32_t i, Visit&& visit) {
  visit(i);
  for (std::size_t b = body.family_offset[i]; b < body.family_offset[i + 1]; ++b)
    if (body.bond_intact[b]) visit(body.family_neighbour[b]);
}

inline ClusterGeometry cluster_geometry(const PointSet& body, std::uint32_t i) {
  ClusterGeometry g;
  const Vec3 xi = body.position(i);
  Vec3 moment = Vec3::Zero();
  for_cluster(body, i, [&](std::uint32_t k) {
    const double m = body.density * body.volume[k];
    g.mass += m;
    moment += m * (body.position(k) - xi);
  });
  g.centre = moment / g.mass;
  for_cluster(body, i, [&](std::uint32_t k) {
    const double m = body.density * body.volume[k];
    const Vec3 rho = (body.position(k) - xi) - g.centre;
    g.inertia += m * (rho.squaredNorm() * Eigen::Matrix3d::Identity() - rho * rho.transpose());
  });
  return g;
}

// J^+ v: in 2D the z component over J_zz; in 3D over the eigenvalues above 1e-10 of the largest.
inline Vec3 pseudo_solve(const PointSet& body, const Eigen::Matrix3d& inertia, const Vec3& v) {
  if (body.dimension == 2) {
    const double jzz = inertia(2, 2);
    return jzz > 0 ? Vec3(0, 0, v.z() / jzz) : Vec3::Zero();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(inertia);
  const Eigen::Vector3d& lambda = eigen.eigenvalues();  // ascending
  Vec3 x = Vec3::Zero();
  const double floor = 1e-10 * lambda(2);
  for (int a = 0; a < 3; ++a)
    if (lambda(a) > floor) {
      const Vec3 axis = eigen.eigenvectors().col(a);
      x += (axis.dot(v) / lambda(a)) * axis;
    }
  return x;
}

}  // namespace detail

// omega = J^+ L of point i's cluster (zero for a point without intact bonds).
inline Vec3 cluster_spin(const PointSet& body, std::uint32_t i) {
  const detail::ClusterGeometry g = detail::cluster_geometry(body, i);
  if (g.mass <= 0) return Vec3::Zero();
  const Vec3 xi = body.position(i);
  // L about c; any common velocity drops out since sum m rho = 0, so v^i is taken out first
  // (a fast-moving cluster then keeps the digits of its spin).
  Vec3 angular = Vec3::Zero();
  const Vec3 vi = body.velocity[i];
  detail::for_cluster(body, i, [&](std::uint32_t k) {
    const double m = body.density * body.volume[k];
    angular += m * ((body.position(k) - xi) - g.centre).cross(body.velocity[k] - vi);
  });
  return detail::pseudo_solve(body, g.inertia, angular);
}

// Adds the forces g_k / V^k = rho mu x rho_k of the couple `torque` to point i's cluster.
inline void add_cluster_couple(const PointSet& body, std::uint32_t i, const Vec3& torque) {
  const detail::ClusterGeometry g = detail::cluster_geometry(body, i);
  if (g.mass <= 0) return;
  const Vec3 mu = detail::pseudo_solve(body, g.inertia, torque);
  const Vec3 xi = body.position(i);
  detail::for_cluster(body, i, [&](std::uint32_t k) {
    body.force_density[k] += body.density * mu.cross((body.position(k) - xi) - g.centre);
  });
}

}  // namespace ckpd
