#pragma once
// Pieces every force model is written with (ckpd_model.hpp explains the law they serve): how a
// kernel holds a set's reference measure, a set's vertex forces and energy, and its
// linearisation at the reference state.
#include <Eigen/Core>
#include <array>
#include <cmath>

#include "bodies/vec.hpp"

namespace ckpd {

// A reference measure R held as its value: m / R is a division.
struct ReferenceMeasure {
  double R;
  double over(double m) const { return m / R; }
  double inverse() const { return 1 / R; }
  double times_square(double e) const { return R * e * e; }
};
// A reference measure held as its inverse (lattice stencil tables): m / R is a product.
struct InverseMeasure {
  double inv;
  double over(double m) const { return m * inv; }
  double inverse() const { return inv; }
  double times_square(double e) const { return e * e / inv; }
};
// A bond length held both ways (the general path divides once, the stencil has both).
struct BondMeasure {
  double L, inv_L;
  double over(double m) const { return m / L; }
  double inverse() const { return inv_L; }
  double times_square(double e) const { return L * e * e; }
};

// Whether a model's kernels use the energy-consistent force form (ckpd_model.hpp,
// ConservativeForm): models without the member use their own family's law.
template <class Model>
constexpr bool conservative_form() {
  if constexpr (requires { Model::kConservative; }) {
    return Model::kConservative;
  } else {
    return false;
  }
}

// sign(0) = 0. (A branch-free form measured 10% slower on lattices, where the orientation of
// consecutive tetrahedra is well predicted.)
inline double sign_of(double v) {
  return v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0);
}

// d2psi/dm2 = C / R of every family's law, for a weight C (the stiffness bound and the
// linearisations use it).
inline double law_curvature(double weight, double R) {
  return weight / R;
}

// The linearisation of one unordered set at its reference state: with g_c the gradient of the
// measure at vertex c there, the force on c (per unit force weight) changes by
//   dF_c = -curvature * g_c (sum_d g_d . du_d),   i.e. dF_c/du_d = -curvature g_c g_d^T,
// because dpsi/dm vanishes at the reference state and only d2psi/dm2 g g^T is left.
template <int kVertices>
struct SetLinearisation {
  double constant = 1;  // C of the law per unit force weight (1, or C1 for bonds)
  double R = 0;         // the reference measure
  std::array<Vec3, kVertices> gradient{};
  // d2psi/dm2 = C/R, scaled by k.
  double curvature(double k = 1) const { return law_curvature(k * constant, R); }
  // dF_c/du_d.
  Eigen::Matrix3d block(int c, int d) const {
    return -curvature() * (gradient[static_cast<std::size_t>(c)] *
                           gradient[static_cast<std::size_t>(d)].transpose());
  }
};

// Forces on the vertices of one unordered set and its energy, per unit force weight: vertex 0 is
// the set's centre, the offsets P.. (reference) and p.. (current) lead from it to the others.
// energy is the ordered-sum energy per unit force weight, so that force_c = -d energy/dx_c.
template <int kVertices>
struct SetTerm {
  std::array<Vec3, kVertices> force{};
  double energy = 0;
  bool inverted = false;
  bool degenerate = false;  // the centre sees the set as degenerate: no term
};

}  // namespace ckpd
