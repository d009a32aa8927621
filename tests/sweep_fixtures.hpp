#pragma once
// A base case small enough to run dozens of times in a test: a 2D steel square of 20 x 20
// points, its left columns fixed, the rest thrown to the right, 20 steps.
#include <filesystem>
#include <string>

#include "run_helpers.hpp"

namespace ckpd::testing {

inline std::string write_sweep_base(const std::filesystem::path& dir) {
  return write_file(dir / "base.yaml", R"(# tiny 2D block; SI units
materials:
  steel: {density: 7850, youngs_modulus: 210e9, poisson_ratio: 0.3, critical_stretch: 0.01}
bodies:
  - name: block
    material: steel
    dimension: 2
    geometry: {type: box, min: [0, 0], max: [0.02, 0.02]}
    spacing: 0.001
    horizon_ratio: 3.015
conditions:
  - {type: initial_velocity, body: block, value: [1.0, 0]}
  - {type: fixed, body: block, region: {type: box, min: [0, 0], max: [0.0025, 0.02]}}
time:
  steps: 20
  dt: auto
  allow_unstable_dt: false
)");
}

}  // namespace ckpd::testing
