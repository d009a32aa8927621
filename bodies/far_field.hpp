#pragma once
// The adaptive linearised far field (issue 20, THEORY.md section 11b). Each step every point is
// classified: *linear* while no bond between two points of its family (itself included) has
// failed and max_j |dx^ij - dX^ij| / L^ij over its family stays below the tolerance T; otherwise
// *exact*, and exact for good (damage is permanent, and the rule keeps the decision cheap and
// sticky). Exact points get the symmetric kernel's exact force: every set with an exact vertex is
// evaluated, because a centre is skipped only when it and its whole upper family are linear,
// and within a centre a set is left out only when none of its vertices is exact (per-set
// masking, SymmetricKernelWorkspace::exact_point: its forces would land on linear rows only).
// Linear points get b^i = sum_c K^ic u^c from the linear operator's row (linear_operator.hpp),
// and the strain energy density linear_energy_density (their share of (1/2) u^T H u).
//
// Corotated (far_field: {tolerance: T, corotated: true}): point i's local rotation R^i, the
// rotation of the polar decomposition of its family's deformation gradient
// F^i = (sum_j dx^ij dX^ijT) (sum_j dX^ij dX^ijT)^-1, is taken out first. The screen becomes
// max_j |R^iT dx^ij - dX^ij| / L^ij < T (it bounds the strain, not the rotation) and a linear
// point's force and energy are those of the corotated relative displacements
// d^ij = R^iT dx^ij - dX^ij: b^i = R^i sum_j K^ij d^ij, W^i = (1/4) sum_j d^ij . K^ij d^ij. A
// rigid motion of any size leaves them at zero; the error against the exact force is of second
// order in the strain, as without rotation.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "bodies/body.hpp"
#include "bodies/linear_operator.hpp"
#include "bodies/symmetric_kernel.hpp"

namespace ckpd {

struct FarField {
  double tolerance = 0;  // > 0 (a body without the key or with T = 0 has no FarField)
  LinearOperator op;     // at the reference state
  // Per point: 1 exact (for good), 0 linear; skip: centre i and all its upper neighbours are
  // linear (the symmetric kernel enumerates nothing from i that an exact point needs).
  std::vector<std::uint8_t> exact, row_failed, skip;
  std::size_t exact_count = 0;
  // Leave out the sets of processed centres that have no exact vertex (the exact rows are the
  // same bit for bit either way; false: every set, for the tests that compare).
  bool mask_sets = true;
  // Corotated: per point the inverse of its family's shape tensor sum_j dX dX^T (2D bodies: in
  // the plane, with 1 out of it) and, for the linear points, R^i as of the last classification.
  bool corotated = false;
  std::vector<Eigen::Matrix3d> shape_inverse, rotation;
  // Not corotated: the linear points' b^i, computed by the classification in the same pass over
  // the family as the screen (both read every member's displacement), for the points the
  // screen passes; exact points' entries are stale.
  std::vector<Vec3> linear_force;
  // Per point, its family's shortest reference bond squared (+inf for an empty family): the
  // screen's bound without a division per bond (classify_far_field).
  std::vector<double> shortest_bond2;
  double exact_fraction() const {
    return exact.empty() ? 0.0
                         : static_cast<double>(exact_count) / static_cast<double>(exact.size());
  }
};

// The far field of a body at its reference state (throws std::invalid_argument for a model
// without a linearisation, as reference_linear_operator does).
FarField make_far_field(const Body& body, double tolerance, bool corotated = false);

// The rotation R of the polar decomposition F = R U (U symmetric positive definite), by Newton's
// iteration X <- (X + X^-T) / 2 from X = F: quadratic near a rotation, and a linear point's F is
// within T of one. False (R untouched) when det F <= 0: an inverted family, never linear.
bool polar_rotation(const Eigen::Matrix3d& F, Eigen::Matrix3d& R);

// Updates ff.exact (sticky), ff.skip and ff.exact_count (and, corotated, ff.rotation; otherwise
// ff.linear_force of the linear points) from the body's bonds and displacements: O(bonds),
// parallel, no allocation after the first call.
void classify_far_field(const Body& body, FarField& ff);

// The body's internal force density (and, with energy, strain energy density) with the far
// field: classification, the symmetric kernel on the centres not skipped, the linear rows.
SymmetricKernelStats compute_internal_force_far_field(Body& body, FarField& ff, bool with_energy);
SymmetricKernelStats compute_internal_force_far_field(Body& body, FarField& ff, bool with_energy,
                                                      SymmetricKernelWorkspace& workspace);

}  // namespace ckpd
