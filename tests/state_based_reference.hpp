#pragma once
// An independent energy of the nonlinear state-based solid for the tests: the formula of
// THEORY.md ("The state-based solid") written out plainly, serially, bond by bond,
//   E = sum_i V_i [lambda_bar theta_i^2 / 2 + mu_bar sum_j w_ij phi_ij eps_ij^2 V_j],
//   theta_i = sum_j w_ij phi_ij eps_ij V_j,
// with its own weight and Seth-Hill strain (no code shared with bodies/state_based_model.cpp;
// only the body's weight factor is taken from it).
#include <cmath>

#include "bodies/body.hpp"

namespace state_based_reference {

inline double weight(const ckpd::Body& b, double r) {
  const double d = b.horizon;
  if (r >= d) return 0;
  const double c =
      b.dimension == 2 ? 10.0 / (M_PI * std::pow(d, 6)) : 315.0 / (16.0 * M_PI * std::pow(d, 7));
  return b.state_based.weight_scale * c * (3 * r + d) * std::pow(d - r, 3);
}

inline double strain(double m, double ratio_squared) {
  if (m == 0) return 0.5 * std::log(ratio_squared);
  return (std::pow(ratio_squared, m) - 1) / (2 * m);
}

inline double energy(const ckpd::Body& b) {
  long double total = 0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    long double theta = 0, squares = 0;
    for (std::size_t k = b.family.offset[i]; k < b.family.offset[i + 1]; ++k) {
      if (!b.bond_intact[k]) continue;
      const std::size_t j = b.family.neighbour[k];
      const ckpd::Vec3 xi = b.reference_position[j] - b.reference_position[i];
      const ckpd::Vec3 y = b.current_position(j) - b.current_position(i);
      const double eps = strain(b.state_based.m, y.squaredNorm() / xi.squaredNorm());
      const double w = weight(b, xi.norm());
      theta += w * eps * b.volume[j];
      squares += w * eps * eps * b.volume[j];
    }
    total += b.volume[i] *
             (0.5 * b.state_based.lambda_bar * theta * theta + b.state_based.mu_bar * squares);
  }
  return static_cast<double>(total);
}

}  // namespace state_based_reference
