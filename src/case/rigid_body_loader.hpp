#pragma once
// Reads a body with a `rigid` key: points on a lattice like any body, no bonds, and a rigid
// motion (src/engine/rigid_body.hpp). Keys: name, rigid {motion: prescribed | free, velocity,
// angular_velocity, mass}, material (its density), dimension, geometry, spacing, max_points.
#include <optional>

#include "src/engine/scene.hpp"
#include "src/input/case_node.hpp"

namespace ckpd {

// `material_density`: the density of the body's `material`, when it names one (read by the
// caller, which knows the materials). Every error is a CaseError naming file, line and key.
SceneBody read_rigid_body(const CaseNode& node, std::optional<double> material_density);

}  // namespace ckpd
