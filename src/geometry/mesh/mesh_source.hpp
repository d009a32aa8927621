#pragma once
// The case-file side of a mesh: `file` (relative to the case file's folder), `scale` (file
// units to metres, > 0, default 1), `rotation: {axis: [x, y, z], degrees: a}` and
// `translation: [x, y, z]` (m), applied as x = R (s X) + t. Reads, places and diagnoses it;
// every failure is a CaseError naming the case file, the key and what was wrong.
#include <memory>
#include <string>

#include "src/geometry/mesh/mesh_check.hpp"
#include "src/geometry/mesh/mesh_info.hpp"
#include "src/geometry/mesh/triangle_mesh.hpp"
#include "src/input/case_node.hpp"

namespace ckpd {

struct LoadedMesh {
  std::shared_ptr<const TriangleMesh> mesh;
  MeshDiagnosis diagnosis;
  MeshInfo info;
};

// Reads the keys above from `node` (other keys are left for the caller) and the file. Errors
// for a missing file, an unknown format, an unparsable file, no triangles and a zero scale;
// `allow_open`: an open surface is not an error (walls, tolerant sampling); degenerate triangles,
// non-manifold and inconsistently wound edges and inverted normals (negative enclosed volume of
// a closed surface) always are (with `allow_open`, degenerate triangles are dropped instead).
LoadedMesh load_mesh(const CaseNode& node, bool allow_open);

}  // namespace ckpd
