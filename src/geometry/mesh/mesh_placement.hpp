#pragma once
// Puts a mesh read from a file where the case wants it, x = R (s X) + t, and into a canonical
// order: vertices sorted by position (unused ones dropped), each triangle starting at its
// smallest vertex index (winding kept), triangles sorted. Two files that describe the same
// surface (any format, any vertex or facet order) give the same mesh, bit for bit, so every
// later computation on it gives the same numbers.
#include <Eigen/Core>

#include "src/geometry/mesh/triangle_mesh.hpp"

namespace ckpd {

struct MeshPlacement {
  double scale = 1;  // file units to metres
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Vec3 translation = Vec3::Zero();
};

TriangleMesh place_mesh(const TriangleMesh& file_mesh, const MeshPlacement& placement);

// The canonical order alone (place_mesh applies it after the transform).
void canonicalise(TriangleMesh& mesh);

}  // namespace ckpd
