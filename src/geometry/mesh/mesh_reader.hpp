#pragma once
// Reads a triangle surface from any file assimp imports (STL, OBJ, PLY, OFF, glTF, ...):
// polygons are triangulated, node transforms applied, and vertices at equal positions welded
// into one, whatever else (normals, texture coordinates) the file gives them. Welding by
// position is what makes an STL file (three vertices per facet) and an indexed OBJ or PLY of the
// same surface the same mesh.
#include <sys/resource.h>

#include <cstdint>
#include <stdexcept>
#include <string>

#include "src/geometry/mesh/triangle_mesh.hpp"

namespace ckpd {

// What was wrong with a mesh file or a mesh; the caller adds the file and the case key.
class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Limits of a mesh import: the file's size (checked before reading), and the importer's CPU
// time and address space (rlimits of the child process it runs in).
inline constexpr std::uintmax_t kMaxMeshFileBytes = std::uintmax_t{1} << 30;  // 1 GiB
inline constexpr rlim_t kMeshImportCpuSeconds = 120;
inline constexpr rlim_t kMeshImportMemoryBytes = rlim_t{8} << 30;  // 8 GiB

// Throws MeshError for a missing file, a format assimp does not read (by extension), a file
// over kMaxMeshFileBytes, a file assimp cannot parse, a file with no triangles (a point cloud
// or a line drawing), and an importer that crashes, aborts or exceeds its limits: assimp runs
// in a child process (fork), which sends the triangle mesh back through a pipe, so that its
// failure is an error naming the importer and the signal, never ckpd's own crash.
TriangleMesh read_mesh_file(const std::string& path);

}  // namespace ckpd
