#pragma once
// `geometry: {type: mesh, file: F, scale: s, rotation: {axis, degrees}, translation: t,
// inside_test: strict | tolerant}`: the solid a triangle surface encloses, for 3D bodies and
// regions. Sampling goes row by row (mesh_inside.hpp) rather than site by site, and refuses
// before allocating when mesh volume / dx^3 exceeds the body's max_points.
#include "src/geometry/mesh/mesh_inside.hpp"
#include "src/geometry/mesh/mesh_source.hpp"
#include "src/geometry/shape.hpp"

namespace ckpd {

class MeshShape : public Shape {
 public:
  MeshShape(LoadedMesh loaded, InsideTest test);
  bool contains(const Vec3& p) const override { return inside_.contains(p); }
  Bounds bounds() const override { return {info_.lo, info_.hi}; }

  LatticeSample sample(double dx, double horizon, std::size_t max_points) const;
  const MeshInfo& info() const { return info_; }
  const TriangleMesh& mesh() const { return *mesh_; }

 private:
  std::shared_ptr<const TriangleMesh> mesh_;
  MeshInfo info_;
  double estimate_volume_;  // enclosed volume, or the box's for an open surface
  MeshInside inside_;
};

}  // namespace ckpd
