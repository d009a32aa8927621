#pragma once
// Inside a triangle surface or not, for single points and for whole lattice rows.
//
// strict (closed surfaces): a point is inside when the signed crossings of the ray from it
// along +x add up to non-zero (its winding number along that ray); points on the surface count
// as inside. On a closed surface every line's crossings add up to zero (axis_rays.hpp); a line
// where they do not (round-off in a sliver) is decided by the vote below.
//
// tolerant (surfaces with holes, asked for explicitly): six half-rays (+-x, +-y, +-z) vote and
// the majority wins (4 of 6; a tie counts as outside). A hole is missed by most of the rays
// through a point, so points near a small hole are classified as if it were closed.
#include <cstddef>
#include <memory>
#include <vector>

#include "src/geometry/lattice.hpp"
#include "src/geometry/mesh/axis_rays.hpp"

namespace ckpd {

enum class InsideTest { strict, tolerant };

class MeshInside {
 public:
  MeshInside(std::shared_ptr<const TriangleMesh> mesh, InsideTest test);

  bool contains(const Vec3& p) const;

  // Cubic lattice sites of spacing dx inside the surface, placed as sample_lattice places them
  // (centred on the mesh's box; same order: x fastest, then y, then z). Throws
  // std::invalid_argument, before allocating the points, when `estimated_points` exceeds
  // `max_points`, and when the count found exceeds it.
  LatticeSample sample(double dx, double horizon, std::size_t max_points,
                       double estimated_points) const;

  // Lines along x whose crossings did not add up to zero in the last strict sampling (decided by
  // the vote instead).
  std::size_t unbalanced_rows() const { return unbalanced_rows_; }

 private:
  bool vote(const Vec3& p) const;
  std::shared_ptr<const TriangleMesh> mesh_;
  InsideTest test_;
  AxisRays rays_[3];
  mutable std::size_t unbalanced_rows_ = 0;
};

}  // namespace ckpd
