#pragma once
// A rigid obstacle given by its triangle surface only: no points inside. Contact points find
// the nearest point of the surface with an FCL distance query against a bounding-volume
// hierarchy (OBBRSS) of the triangles; the exact nearest point is then computed on the triangle
// FCL returns and its neighbours, and which side the point is on comes from the angle-weighted
// pseudo-normal of the nearest feature (face, edge or vertex; Baerentzen and Aanaes 2005), so
// it is right at edges and corners too.
//
// The wall's motion is that of a rigid body of six carrier points, c0 +- a_k e_k along the
// principal axes of its solid (or the coordinate axes of a wall without one): with volumes V/6
// they have the solid's volume, centroid and inertia tensor exactly, so the engine's rigid
// motion (src/engine/rigid_body.hpp) moves, integrates and books a mesh wall like any rigid
// body. The wall's pose follows from where its carriers are.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "contact/broad_phase.hpp"
#include "contact/point_set.hpp"

namespace ckpd {

struct WallCarriers {
  Vec3 centre = Vec3::Zero();                          // c0
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  // e_k as columns, right-handed
  Vec3 half_length = Vec3::Ones();                     // a_k
  // The six points: c0 + a_0 e_0, c0 - a_0 e_0, c0 + a_1 e_1, ...
  std::vector<Vec3> points() const;
};

// Carriers with the volume, centroid and second moment J (integral of |r|^2 I - r r^T over
// the solid): a_k^2 = 3 (J_l + J_m - J_k) / (2 V) from J's principal values.
WallCarriers carriers_from_moments(double volume, const Vec3& centroid,
                                   const Eigen::Matrix3d& second_moment);

class MeshWall {
 public:
  MeshWall(std::vector<Vec3> vertex, std::vector<std::array<std::uint32_t, 3>> triangle,
           WallCarriers carriers);
  ~MeshWall();
  MeshWall(const MeshWall&) = delete;
  MeshWall& operator=(const MeshWall&) = delete;

  const WallCarriers& carriers() const { return carriers_; }
  std::size_t triangles() const { return triangle_.size(); }
  // The reference surface's box.
  const Box3& box() const { return box_; }

  // Where the wall is: x = centre + R (X - c0), from its carrier points' current positions.
  struct Pose {
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    Vec3 centre = Vec3::Zero();
  };
  Pose pose(const PointSet& carriers) const;

  struct Nearest {
    Vec3 point;         // on the surface, reference frame
    Vec3 outward;       // unit: from the surface towards the outside, through X when X is off it
    double height = 0;  // signed distance: > 0 outside (the side the normals point to)
    std::uint32_t triangle = 0;
  };
  // The nearest surface point to X (reference frame) if closer than `radius`.
  std::optional<Nearest> nearest(const Vec3& X, double radius) const;

 private:
  struct Bvh;
  std::vector<Vec3> vertex_;
  std::vector<std::array<std::uint32_t, 3>> triangle_;
  std::vector<Vec3> face_normal_;                  // unit
  std::vector<std::array<Vec3, 3>> edge_normal_;   // per triangle, edge k = corner k -> k+1
  std::vector<Vec3> vertex_normal_;                // angle-weighted
  std::vector<std::uint32_t> ring_offset_, ring_;  // triangles around each vertex (CSR)
  WallCarriers carriers_;
  Box3 box_;
  std::unique_ptr<Bvh> bvh_;
};

}  // namespace ckpd
