#pragma once
// The force law's linearisation at the reference state (issue 20, the far field's operator):
// b^i = sum_c K^ic u^c to first order in the displacements, one 3 x 3 block per point c of
// i's family and one for i itself. Each set contributes its linearisation (set_law.hpp,
// SetLinearisation: dF_c/du_d = -C/R g_c g_d^T, the measure's gradients g at the reference
// state) with the weights of the force form in force:
// - own_family (MODEL.md): row i takes the sets of i's own family with i's weights
//   dV1^i, k2^i, k3^i (the plain Jacobian; not symmetric near surfaces);
// - energy_consistent: every point c's sets give every vertex d the share V^c w^c / ((n+1) V^d)
//   (THEORY.md section 2b): the Hessian of the energy, divided by the receiving point's volume.
// Sets switched off by failed bonds (under the body's damage rule) and sets degenerate at the
// reference state contribute nothing, as in the kernels. The inversion penalty is zero at the
// reference state and every Seth-Hill measure has the same linearisation there (e_m'(1) = 1).
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "bodies/body.hpp"

namespace ckpd {

struct LinearOperator {
  // Row i's blocks are block[offset[i] .. offset[i + 1]): first d b^i / d u^i, then
  // d b^i / d u^j for the members j of i's family in the order of body.family's row.
  std::vector<std::size_t> offset;
  std::vector<Eigen::Matrix3d> block;
  std::size_t bytes() const {
    return block.size() * sizeof(Eigen::Matrix3d) + offset.size() * sizeof(std::size_t);
  }
};

// Throws std::invalid_argument for a model without set linearisations (the state-based solid).
LinearOperator reference_linear_operator(const Body& body);

// b^i = sum_c K^ic u^c with the body's displacements, for every point.
void apply_linear_operator(const LinearOperator& op, const Body& body, std::vector<Vec3>& b);

}  // namespace ckpd
