#pragma once
// Volume, centroid and second moments of the solid a closed, outward-wound triangle surface
// bounds, by the divergence theorem: each triangle and the origin span a tetrahedron whose
// signed integrals add up (D. Eberly, "Polyhedral Mass Properties (Revisited)", 2002).
#include <Eigen/Core>

#include "src/geometry/mesh/triangle_mesh.hpp"

namespace ckpd {

struct MeshMassProperties {
  double volume = 0;
  Vec3 centroid = Vec3::Zero();
  // Integral over the solid of (|r|^2 I - r r^T) with r from the centroid: the inertia tensor
  // per unit density, m^5.
  Eigen::Matrix3d second_moment = Eigen::Matrix3d::Zero();
};

MeshMassProperties mesh_mass_properties(const TriangleMesh& mesh);

}  // namespace ckpd
