#include "src/case/mesh_wall_loader.hpp"

#include "src/geometry/mesh/mesh_properties.hpp"
#include "src/geometry/mesh/mesh_source.hpp"

namespace ckpd {

SceneBody read_mesh_wall(const CaseNode& n, const CaseNode& w, const std::string& name,
                         RigidMotion::Kind kind, const Vec3& velocity, const Vec3& angular_velocity,
                         std::optional<double> mass, std::optional<double> material_density) {
  const bool free = kind == RigidMotion::Kind::free;
  LoadedMesh loaded = load_mesh(w, !free);
  w.finish();
  n.finish();
  const TriangleMesh& mesh = *loaded.mesh;
  WallCarriers carriers;
  double volume = 0;
  if (loaded.info.closed) {
    const MeshMassProperties props = mesh_mass_properties(mesh);
    volume = props.volume;
    carriers = carriers_from_moments(props.volume, props.centroid, props.second_moment);
  } else {
    // No solid: the carriers only give the pose (pivot at the box centre) and carry the mass of
    // rigid.mass, if any; their volume is a nominal 1 m^3.
    Vec3 lo, hi;
    mesh.bounds(lo, hi);
    carriers.centre = 0.5 * (lo + hi);
    carriers.half_length = 0.5 * (hi - lo);
    volume = 1;
  }
  const double density = mass ? *mass / volume : material_density.value_or(0.0);
  SceneBody sb;
  sb.spacing = 0;  // no lattice: contact radii come from the partners' spacing
  try {
    sb.body =
        make_point_set(name, 3, carriers.points(), std::vector<double>(6, volume / 6), density);
    sb.rigid.emplace(sb.body, kind, velocity, angular_velocity);
  } catch (const std::invalid_argument& e) {
    throw CaseError(n.where() + ": " + e.what());
  }
  sb.wall = std::make_shared<const MeshWall>(mesh.vertex, mesh.triangle, carriers);
  sb.mesh = loaded.info;
  sb.mesh->wall = true;
  return sb;
}

}  // namespace ckpd
