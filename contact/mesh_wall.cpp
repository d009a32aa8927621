#include "contact/mesh_wall.hpp"

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/distance.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <map>

namespace ckpd {

std::vector<Vec3> WallCarriers::points() const {
  std::vector<Vec3> p;
  for (int k = 0; k < 3; ++k) {
    p.push_back(centre + half_length[k] * axes.col(k));
    p.push_back(centre - half_length[k] * axes.col(k));
  }
  return p;
}

WallCarriers carriers_from_moments(double volume, const Vec3& centroid,
                                   const Eigen::Matrix3d& second_moment) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(second_moment);
  WallCarriers c;
  c.centre = centroid;
  c.axes = eig.eigenvectors();
  if (c.axes.determinant() < 0) c.axes.col(2) = -c.axes.col(2);
  const Vec3 J = eig.eigenvalues();
  // A pair at +-a along e_k adds 2 (V/6) a^2 to the moments about the other two axes.
  for (int k = 0; k < 3; ++k) {
    const double a2 = 3 * (J[(k + 1) % 3] + J[(k + 2) % 3] - J[k]) / (2 * volume);
    c.half_length[k] = std::sqrt(std::max(a2, 0.0));
  }
  return c;
}

struct MeshWall::Bvh {
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> model;
  std::shared_ptr<fcl::Sphered> probe;
};

MeshWall::MeshWall(std::vector<Vec3> vertex, std::vector<std::array<std::uint32_t, 3>> triangle,
                   WallCarriers carriers)
    : vertex_(std::move(vertex)), triangle_(std::move(triangle)), carriers_(carriers) {
  const std::size_t nt = triangle_.size(), nv = vertex_.size();
  box_ = {Vec3::Constant(INFINITY), Vec3::Constant(-INFINITY)};
  for (const Vec3& v : vertex_) {
    box_.lo = box_.lo.cwiseMin(v);
    box_.hi = box_.hi.cwiseMax(v);
  }
  // Pseudo-normals: faces; edges the sum of their (one or two) faces; vertices the sum of their
  // faces weighted by the corner angle.
  face_normal_.resize(nt);
  vertex_normal_.assign(nv, Vec3::Zero());
  std::map<std::pair<std::uint32_t, std::uint32_t>, Vec3> edge_sum;
  std::vector<std::uint32_t> count(nv + 1, 0);
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& tri = triangle_[t];
    const Vec3 n = (vertex_[tri[1]] - vertex_[tri[0]]).cross(vertex_[tri[2]] - vertex_[tri[0]]);
    face_normal_[t] = n.normalized();
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = tri[k], b = tri[(k + 1) % 3], c = tri[(k + 2) % 3];
      // try_emplace with an explicit zero: map's operator[] default-constructs the Vec3, which
      // Eigen leaves uninitialised (valgrind found the sum starting from garbage: edge normals,
      // and so the wall's contact forces, that varied from run to run).
      edge_sum.try_emplace({std::min(a, b), std::max(a, b)}, Vec3::Zero()).first->second +=
          face_normal_[t];
      const Vec3 u = (vertex_[b] - vertex_[a]).normalized(),
                 w = (vertex_[c] - vertex_[a]).normalized();
      vertex_normal_[a] += std::acos(std::clamp(u.dot(w), -1.0, 1.0)) * face_normal_[t];
      ++count[a + 1];
    }
  }
  edge_normal_.resize(nt);
  for (std::size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = triangle_[t][k], b = triangle_[t][(k + 1) % 3];
      edge_normal_[t][k] = edge_sum.at({std::min(a, b), std::max(a, b)}).normalized();
    }
  for (Vec3& n : vertex_normal_) n.normalize();
  ring_offset_ = count;
  for (std::size_t v = 1; v <= nv; ++v) ring_offset_[v] += ring_offset_[v - 1];
  ring_.resize(ring_offset_.back());
  std::vector<std::uint32_t> fill(ring_offset_.begin(), ring_offset_.end() - 1);
  for (std::uint32_t t = 0; t < nt; ++t)
    for (std::uint32_t v : triangle_[t]) ring_[fill[v]++] = t;

  bvh_ = std::make_unique<Bvh>();
  bvh_->model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  std::vector<fcl::Vector3d> points(vertex_.begin(), vertex_.end());
  std::vector<fcl::Triangle> tris;
  for (const auto& t : triangle_) tris.emplace_back(t[0], t[1], t[2]);
  bvh_->model->beginModel();
  bvh_->model->addSubModel(points, tris);
  bvh_->model->endModel();
  // A point is queried as a tiny sphere; its radius is added back to the distance.
  const double size = (box_.hi - box_.lo).norm();
  bvh_->probe = std::make_shared<fcl::Sphered>(1e-12 * std::max(size, 1e-300));
}

MeshWall::~MeshWall() = default;

MeshWall::Pose MeshWall::pose(const PointSet& body) const {
  Vec3 x[6];
  Pose p;
  for (int k = 0; k < 6; ++k) {
    x[k] = body.position(static_cast<std::size_t>(k));
    p.centre += x[k] / 6;
  }
  // R e_k = (x_+ - x_-) / (2 a_k); an axis without extent follows from the other two.
  Eigen::Matrix3d moved;
  int flat = -1;
  const double longest = carriers_.half_length.maxCoeff();
  for (int k = 0; k < 3; ++k) {
    if (carriers_.half_length[k] > 1e-9 * longest)
      moved.col(k) = ((x[2 * k] - x[2 * k + 1]) / (2 * carriers_.half_length[k])).normalized();
    else
      flat = k;
  }
  if (flat >= 0)
    moved.col(flat) = moved.col((flat + 1) % 3).cross(moved.col((flat + 2) % 3)).normalized();
  p.rotation = moved * carriers_.axes.transpose();
  return p;
}

namespace {

// Ericson, Real-Time Collision Detection 5.1.5: the point of triangle abc nearest to p, and
// which feature it is on: 0-2 vertex k, 3-5 edge k (corner k -> k+1), 6 the face.
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, int& feature) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return feature = 0, a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return feature = 1, b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return feature = 3, a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return feature = 2, c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return feature = 5, a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return feature = 4, b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = 1 / (va + vb + vc);
  return feature = 6, a + ab * (vb * denom) + ac * (vc * denom);
}

}  // namespace

std::optional<MeshWall::Nearest> MeshWall::nearest(const Vec3& X, double radius) const {
  for (int d = 0; d < 3; ++d)
    if (X[d] < box_.lo[d] - radius || X[d] > box_.hi[d] + radius) return std::nullopt;
  fcl::DistanceRequestd request(false);
  fcl::DistanceResultd result;
  fcl::distance(bvh_->model.get(), fcl::Transform3d::Identity(), bvh_->probe.get(),
                fcl::Transform3d(Eigen::Translation3d(X)), request, result);
  // FCL's answer within its tolerance; the exact one over that triangle and its neighbours
  // (all triangles when the probe touched the surface and FCL gave no triangle).
  std::vector<std::uint32_t> candidates;
  if (result.min_distance > 0 && result.b1 >= 0 &&
      static_cast<std::size_t>(result.b1) < triangle_.size()) {
    if (result.min_distance > radius) return std::nullopt;
    for (std::uint32_t v : triangle_[static_cast<std::size_t>(result.b1)])
      for (std::uint32_t k = ring_offset_[v]; k < ring_offset_[v + 1]; ++k)
        candidates.push_back(ring_[k]);
  } else {
    for (std::uint32_t t = 0; t < triangle_.size(); ++t) candidates.push_back(t);
  }
  double best = INFINITY;
  Nearest n;
  int best_feature = 6;
  for (std::uint32_t t : candidates) {
    int feature = 6;
    const auto& tri = triangle_[t];
    const Vec3 q =
        closest_on_triangle(X, vertex_[tri[0]], vertex_[tri[1]], vertex_[tri[2]], feature);
    const double d2 = (X - q).squaredNorm();
    // Ties (a point nearest to a shared edge or vertex) go to the lowest triangle index.
    if (d2 < best || (d2 == best && t < n.triangle)) {
      best = d2;
      n.point = q;
      n.triangle = t;
      best_feature = feature;
    }
  }
  const double distance = std::sqrt(best);
  if (!(distance < radius)) return std::nullopt;
  const auto& tri = triangle_[n.triangle];
  const Vec3 pseudo = best_feature < 3   ? vertex_normal_[tri[best_feature]]
                      : best_feature < 6 ? edge_normal_[n.triangle][best_feature - 3]
                                         : face_normal_[n.triangle];
  const Vec3 off = X - n.point;
  const bool outside = off.dot(pseudo) >= 0;
  n.height = outside ? distance : -distance;
  n.outward =
      distance > 1e-12 * radius ? (outside ? off : -off) / distance : face_normal_[n.triangle];
  return n;
}

}  // namespace ckpd
