#pragma once
// A rigid body with `mesh_wall: {file, scale, rotation, translation}` instead of a geometry: a
// wall given by its surface (contact/mesh_wall.hpp). A fixed or prescribed wall may be an open
// surface (a floor made of two triangles; its normals point to the side that is outside); a
// free one needs a closed surface, whose volume, centroid and inertia give its mass properties
// with the density of its material (or its rigid.mass).
#include <optional>
#include <string>

#include "src/engine/scene.hpp"
#include "src/input/case_node.hpp"

namespace ckpd {

SceneBody read_mesh_wall(const CaseNode& body_node, const CaseNode& wall_node,
                         const std::string& name, RigidMotion::Kind kind, const Vec3& velocity,
                         const Vec3& angular_velocity, std::optional<double> mass,
                         std::optional<double> material_density);

}  // namespace ckpd
