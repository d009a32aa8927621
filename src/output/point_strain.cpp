#include "src/output/point_strain.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <limits>

namespace ckpd {

Eigen::Matrix3d deformation_gradient(const Body& body, std::size_t i) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  if (body.family.offset.size() != body.size() + 1) return Eigen::Matrix3d::Constant(nan);  // rigid
  Eigen::Matrix3d K = Eigen::Matrix3d::Zero(), N = Eigen::Matrix3d::Zero();
  const Vec3 Xi = body.reference_position[i], xi = body.current_position(i);
  for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k) {
    if (!body.bond_intact[k]) continue;
    const std::uint32_t j = body.family.neighbour[k];
    const Vec3 xi_ref = body.reference_position[j] - Xi;
    const Vec3 eta = body.current_position(j) - xi;
    K += body.volume[j] * xi_ref * xi_ref.transpose();
    N += body.volume[j] * eta * xi_ref.transpose();
  }
  const int d = body.dimension;
  // The bonds must span the dimension: K's smallest eigenvalue not negligible next to its largest.
  const Eigen::MatrixXd Kd = K.topLeftCorner(d, d);
  const Eigen::VectorXd eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Kd).eigenvalues();
  if (!(eig.maxCoeff() > 0) || eig.minCoeff() < 1e-10 * eig.maxCoeff())
    return Eigen::Matrix3d::Constant(nan);
  if (d == 2) {
    K(2, 2) = 1;
    N(2, 2) = 1;
  }
  return N * K.inverse();
}

}  // namespace ckpd
