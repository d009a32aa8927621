#pragma once
// The patch test of MODEL.md section 2: an interior lattice point under a homogeneous small
// strain x = (I + e) X; the ratio of its strain-energy density W1/2 + W2/3 + W3/4 to the
// continuum's lambda/2 tr(e)^2 + mu e:e is the discretisation's stiffness error.
#include <cstdint>

#include "bodies/material.hpp"

namespace ckpd {

struct PatchTestResult {
  std::uint32_t n1 = 0, n2 = 0, n3 = 0;  // ordered, non-degenerate sets of the interior point
  double volumetric = 0;                 // e = eps I
  double shear = 0;                      // e_xy = e_yx = eps
  double uniaxial = 0;                   // e_xx = eps
};

// Cubic (3D) or square (2D) lattice of unit spacing, horizon m. N2 and N3 are counted even when
// C2 or C3 is zero, so a user sees the sets a discretisation has.
PatchTestResult run_patch_test(int dimension, double horizon_ratio, double youngs_modulus,
                               double poisson_ratio, PlaneMode plane, double strain = 1e-6);

}  // namespace ckpd
