#pragma once
// Reads a triangle surface from any file assimp imports (STL, OBJ, PLY, OFF, glTF, ...):
// polygons are triangulated, node transforms applied, and vertices at equal positions welded
// into one, whatever else (normals, texture coordinates) the file gives them. Welding by
// position is what makes an STL file (three vertices per facet) and an indexed OBJ or PLY of the
// same surface the same mesh.
#include <stdexcept>
#include <string>

#include "src/geometry/mesh/triangle_mesh.hpp"

namespace ckpd {

// What was wrong with a mesh file or a mesh; the caller adds the file and the case key.
class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws MeshError for a missing file, a format assimp does not read (by extension), a file
// assimp cannot parse, and a file with no triangles (a point cloud or a line drawing).
TriangleMesh read_mesh_file(const std::string& path);

}  // namespace ckpd
