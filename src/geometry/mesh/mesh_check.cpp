#include "src/geometry/mesh/mesh_check.hpp"

#include <algorithm>
#include <sstream>
#include <tuple>

namespace ckpd {

namespace {

void record(MeshDefect& d, const Vec3& where) {
  if (d.count++ == 0) d.first = where;
}

}  // namespace

MeshDiagnosis diagnose_mesh(const TriangleMesh& mesh) {
  MeshDiagnosis r;
  r.triangles = mesh.triangle.size();
  // (smaller vertex, larger vertex, +1 if the triangle runs small -> large, else -1)
  std::vector<std::tuple<std::uint32_t, std::uint32_t, int>> edges;
  edges.reserve(3 * mesh.triangle.size());
  for (std::size_t t = 0; t < mesh.triangle.size(); ++t) {
    const auto& tri = mesh.triangle[t];
    const Vec3 centroid = (mesh.corner(t, 0) + mesh.corner(t, 1) + mesh.corner(t, 2)) / 3;
    const Vec3 n = mesh.area_normal(t);
    double longest = 0;
    for (int k = 0; k < 3; ++k)
      longest = std::max(longest, (mesh.corner(t, (k + 1) % 3) - mesh.corner(t, k)).squaredNorm());
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0] || !(n.norm() > 1e-10 * longest)) {
      record(r.degenerate, centroid);
      continue;
    }
    r.area += 0.5 * n.norm();
    r.signed_volume += mesh.corner(t, 0).dot(mesh.corner(t, 1).cross(mesh.corner(t, 2))) / 6;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = tri[k], b = tri[(k + 1) % 3];
      edges.emplace_back(std::min(a, b), std::max(a, b), a < b ? 1 : -1);
    }
  }
  std::sort(edges.begin(), edges.end());
  for (std::size_t e = 0; e < edges.size();) {
    std::size_t f = e;
    int direction = 0;
    while (f < edges.size() && std::get<0>(edges[f]) == std::get<0>(edges[e]) &&
           std::get<1>(edges[f]) == std::get<1>(edges[e]))
      direction += std::get<2>(edges[f++]);
    const Vec3 mid =
        0.5 * (mesh.vertex[std::get<0>(edges[e])] + mesh.vertex[std::get<1>(edges[e])]);
    const std::size_t uses = f - e;
    if (uses == 1)
      record(r.open_edges, mid);
    else if (uses > 2)
      record(r.non_manifold, mid);
    else if (direction != 0)
      record(r.misoriented, mid);
    e = f;
  }
  return r;
}

std::string describe(const MeshDefect& d, const std::string& what) {
  if (d.count == 0) return "";
  std::ostringstream s;
  s << d.count << " " << what << ", the first at (" << d.first.x() << ", " << d.first.y() << ", "
    << d.first.z() << ") m";
  return s.str();
}

}  // namespace ckpd
