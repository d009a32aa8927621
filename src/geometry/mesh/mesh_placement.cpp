#include "src/geometry/mesh/mesh_placement.hpp"

#include <algorithm>
#include <numeric>

namespace ckpd {

namespace {

bool position_less(const Vec3& a, const Vec3& b) {
  return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
}

}  // namespace

void canonicalise(TriangleMesh& mesh) {
  std::vector<std::uint8_t> used(mesh.vertex.size(), 0);
  for (const auto& t : mesh.triangle)
    for (std::uint32_t v : t) used[v] = 1;
  std::vector<std::uint32_t> order;
  for (std::uint32_t v = 0; v < mesh.vertex.size(); ++v)
    if (used[v]) order.push_back(v);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return position_less(mesh.vertex[a], mesh.vertex[b]);
  });
  std::vector<std::uint32_t> new_index(mesh.vertex.size(), 0);
  std::vector<Vec3> vertex(order.size());
  for (std::uint32_t k = 0; k < order.size(); ++k) {
    new_index[order[k]] = k;
    vertex[k] = mesh.vertex[order[k]];
  }
  mesh.vertex = std::move(vertex);
  for (auto& t : mesh.triangle) {
    for (auto& v : t) v = new_index[v];
    // Rotate (not reflect) so the smallest index comes first: the winding stays.
    const int first = static_cast<int>(std::min_element(t.begin(), t.end()) - t.begin());
    std::rotate(t.begin(), t.begin() + first, t.end());
  }
  std::sort(mesh.triangle.begin(), mesh.triangle.end());
}

TriangleMesh place_mesh(const TriangleMesh& file_mesh, const MeshPlacement& p) {
  TriangleMesh mesh = file_mesh;
  for (Vec3& v : mesh.vertex) v = p.rotation * (p.scale * v) + p.translation;
  canonicalise(mesh);
  return mesh;
}

}  // namespace ckpd
