#pragma once
// What is wrong with a triangle surface, if anything: degenerate triangles, open edges (holes),
// non-manifold edges, edges whose two triangles are wound the same way (inconsistent
// orientation), and the signed volume (negative: the normals point inwards). Each defect comes
// with its count and the position of the first one, so an error can say where to look.
#include <cstddef>
#include <string>

#include "src/geometry/mesh/triangle_mesh.hpp"

namespace ckpd {

struct MeshDefect {
  std::size_t count = 0;
  Vec3 first = Vec3::Zero();  // centre of the first one (edge midpoint or triangle centroid)
};

struct MeshDiagnosis {
  std::size_t triangles = 0;
  MeshDefect degenerate;     // repeated vertex or area <= 1e-10 x (longest edge)^2
  MeshDefect open_edges;     // edges of one triangle only
  MeshDefect non_manifold;   // edges of three or more triangles
  MeshDefect misoriented;    // edges of two triangles that run along it the same way
  double signed_volume = 0;  // divergence theorem; the enclosed volume for a closed surface
  double area = 0;
  bool closed() const {
    return open_edges.count == 0 && non_manifold.count == 0 && misoriented.count == 0;
  }
};

MeshDiagnosis diagnose_mesh(const TriangleMesh& mesh);

// "N open edges (holes), the first at (x, y, z) m" and the like; empty for no defect.
std::string describe(const MeshDefect& defect, const std::string& what);

}  // namespace ckpd
