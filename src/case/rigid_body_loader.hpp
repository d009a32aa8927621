#pragma once
// Reads a body with a `rigid` key: points on a lattice like any body, no bonds, and a rigid
// motion (src/engine/rigid_body.hpp). Keys: name, rigid {motion: prescribed | free, velocity,
// angular_velocity, mass, density, youngs_modulus, poisson_ratio}, material (its density, E and
// nu), dimension, and geometry with spacing and max_points, or mesh_wall, or dem_sphere {center,
// radius}: a DEM sphere, one point at its centre with the solid sphere's inertia 2/5 m R^2 and
// the contact radius R (contact/contact_settings.hpp). E and nu serve contact laws that use them.
#include <optional>

#include "src/engine/scene.hpp"
#include "src/input/case_node.hpp"

namespace ckpd {

// `material_density`, `material_elastic`: the density and E, nu of the body's `material`, when it
// names one (read by the caller, which knows the materials). Every error is a CaseError naming
// file, line and key.
SceneBody read_rigid_body(const CaseNode& node, std::optional<double> material_density,
                          std::optional<ElasticConstants> material_elastic = std::nullopt);

}  // namespace ckpd
