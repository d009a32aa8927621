#include "src/geometry/mesh/mesh_source.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "src/geometry/mesh/mesh_placement.hpp"
#include "src/geometry/mesh/mesh_reader.hpp"

namespace ckpd {

namespace {

Eigen::Matrix3d read_rotation(const CaseNode& r) {
  const CaseNode axis_node = r.required("axis");
  const Vec3 axis = axis_node.as_vector(3);
  if (!(axis.norm() > 0)) axis_node.fail("a non-zero rotation axis");
  const double degrees = r.required("degrees").as_double();
  r.finish();
  return Eigen::AngleAxisd(degrees * std::numbers::pi / 180, axis.normalized()).toRotationMatrix();
}

}  // namespace

LoadedMesh load_mesh(const CaseNode& node, bool allow_open) {
  const CaseNode file_node = node.required("file");
  std::filesystem::path path = file_node.as_string();
  if (path.is_relative()) path = std::filesystem::path(node.file()).parent_path() / path;
  MeshPlacement placement;
  if (auto s = node.optional("scale")) placement.scale = s->as_positive();
  if (auto r = node.optional("rotation")) placement.rotation = read_rotation(*r);
  if (auto t = node.optional("translation")) placement.translation = t->as_vector(3);

  TriangleMesh file_mesh;
  try {
    file_mesh = read_mesh_file(path.string());
  } catch (const MeshError& e) {
    file_node.fail(e.what());
  }
  LoadedMesh out;
  TriangleMesh mesh = place_mesh(file_mesh, placement);
  MeshDiagnosis d = diagnose_mesh(mesh);
  auto fail = [&](const std::string& what) {
    throw CaseError(file_node.where() + ": mesh " + path.string() + ": " + what);
  };
  if (d.degenerate.count) {
    if (!allow_open)
      fail(describe(d.degenerate, "degenerate triangles (repeated corners or no area)") +
           "; repair the mesh, or sample it with inside_test: tolerant, which drops them");
    std::erase_if(mesh.triangle, [&](const auto& t) {
      const Vec3 n =
          (mesh.vertex[t[1]] - mesh.vertex[t[0]]).cross(mesh.vertex[t[2]] - mesh.vertex[t[0]]);
      double longest = 0;
      for (int k = 0; k < 3; ++k)
        longest =
            std::max(longest, (mesh.vertex[t[(k + 1) % 3]] - mesh.vertex[t[k]]).squaredNorm());
      return t[0] == t[1] || t[1] == t[2] || t[2] == t[0] || !(n.norm() > 1e-10 * longest);
    });
    if (mesh.triangle.empty()) fail("every triangle is degenerate");
    canonicalise(mesh);
    const MeshDefect dropped = d.degenerate;
    d = diagnose_mesh(mesh);
    d.degenerate = dropped;
  }
  if (d.non_manifold.count)
    fail(describe(d.non_manifold, "non-manifold edges (shared by three or more triangles)"));
  if (d.misoriented.count)
    fail(describe(d.misoriented,
                  "edges whose two triangles are wound the same way (inconsistent orientation)"));
  if (d.open_edges.count && !allow_open)
    fail("the surface is not closed: " + describe(d.open_edges, "open edges (holes)") +
         "; close it, or ask for inside_test: tolerant");
  if (d.closed() && !(d.signed_volume > 0))
    fail("the normals point inwards (enclosed volume " + std::to_string(d.signed_volume) +
         " m^3 is not positive); flip the triangles' winding");
  out.info.file = path.string();
  out.info.triangles = mesh.triangle.size();
  mesh.bounds(out.info.lo, out.info.hi);
  out.info.closed = d.closed();
  out.info.open_edges = d.open_edges.count;
  out.info.mesh_volume = d.signed_volume;
  out.diagnosis = d;
  out.mesh = std::make_shared<const TriangleMesh>(std::move(mesh));
  return out;
}

}  // namespace ckpd
