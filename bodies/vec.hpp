#pragma once
// Points are 3-vectors in every dimension: a 2D body lies in the z = 0 plane, so one set of
// kernels serves both (2D cross products point along z).
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ckpd {
using Vec3 = Eigen::Vector3d;
}  // namespace ckpd
