#pragma once
// The patch test of THEORY.md section 2: an interior lattice point under a homogeneous small
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

// The same test with given constants (for the unit lattice: spacing 1, horizon m) and the CKPD
// strain measure (BodyDefinition::strain_measure; 1/2: l/L - 1).
PatchTestResult run_patch_test(int dimension, double horizon_ratio, double youngs_modulus,
                               double poisson_ratio, PlaneMode plane,
                               const InteractionConstants& constants, double strain = 1e-6,
                               double strain_measure = 0.5);

// Calibrated constants: C1 and C3 (3D) or C1 and C2 (2D) chosen so that an interior point of the
// cubic (square) lattice of this spacing and horizon has exactly the continuum's strain-energy
// density under volumetric (e = eps I) and uniaxial (e_xx = eps) strain, i.e. the continuum's
// bulk modulus and P-wave modulus lambda + 2 mu. The energy of a homogeneous strain is linear in
// the constants, so the two unknowns solve a 2 x 2 linear system whose matrix depends only on
// the lattice and m (not on E or nu): it is regular whenever the point has two- (three-)
// neighbour sets, i.e. m >= sqrt(2) (2D and 3D); below that std::invalid_argument is thrown.
// The constants are solved for, not scaled, so nu = 1/4 (3D) and 1/3 (2D plane stress), where
// the analytic C3 (C2) is 0, are not singular: the calibrated constant is then small but not 0,
// and the family is built. The shear ratio (e_xy = e_yx = eps) is not calibrated: a cubic
// (square) lattice is anisotropic, and what is left of its error is the lattice's anisotropy.
InteractionConstants calibrated_constants(int dimension, double youngs_modulus,
                                          double poisson_ratio, PlaneMode plane, double horizon,
                                          double spacing);

}  // namespace ckpd
