#pragma once
// A steel ball of about 33 points (3D, SI units), the smallest case the input tests run: the
// materials and bodies sections, to which a test appends its conditions and time.
#include <string>

namespace ckpd::testing {

inline std::string steel_ball_case(const std::string& rest) {
  return R"(# a small steel ball, SI units
materials:
  steel: {density: 7850, youngs_modulus: 210e9, poisson_ratio: 0.3}
bodies:
  - {name: ball, material: steel, geometry: {type: sphere, center: [0, 0, 0], radius: 0.002},
     spacing: 0.001, horizon_ratio: 3.015}
)" + rest;
}

}  // namespace ckpd::testing
