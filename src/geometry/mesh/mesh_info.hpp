#pragma once
// What `ckpd check` reports of a mesh body: a plain record, so that the scene can carry it without
// depending on mesh loading.
#include <cstddef>
#include <string>

#include "bodies/vec.hpp"

namespace ckpd {

struct MeshInfo {
  std::string file;  // as resolved
  std::size_t triangles = 0;
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  // bounding box, m
  bool closed = false;
  std::size_t open_edges = 0;
  double mesh_volume = 0;  // enclosed (signed) volume, m^3
  bool wall = false;       // a mesh wall (no points inside)
};

}  // namespace ckpd
