#pragma once
// Per-point strain measures for field output, from the body's state alone: the non-local
// deformation gradient of peridynamic correspondence models (Silling et al. 2007, "Peridynamic
// states and constitutive modeling"), with a uniform influence function over the point's
// intact bonds,
//   K = sum_j xi xi^T V_j,  F = (sum_j eta xi^T V_j) K^-1,  xi = X_j - X_i, eta = x_j - x_i,
// which is exact for every point (surface points included) under a homogeneous deformation,
// the Green-Lagrange strain E = (F^T F - I) / 2 and the dilatation det F - 1 (the relative change
// of volume; of area in 2D). A point whose intact bonds do not span its dimension (a point
// broken free) has no estimate: its values are NaN.
#include <Eigen/Core>
#include <cstddef>

#include "bodies/body.hpp"

namespace ckpd {

// Row-major 3 x 3; in 2D the z row and column are those of the identity.
Eigen::Matrix3d deformation_gradient(const Body& body, std::size_t i);

}  // namespace ckpd
