// The CKPD model type (bodies/ckpd_model.hpp), family by family, against references that do not
// come from it: each set's vertex forces are minus the finite-difference gradient of its energy,
// its linearisation at the reference state is the finite-difference Jacobian of its forces, the
// energy vanishes at the reference state and is MODEL.md's psi, and the damage rule is the
// critical stretch.
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "bodies/ckpd_model.hpp"
#include "set_term_checks.hpp"

namespace {

using ckpd::CkpdModel;
using ckpd::Vec3;
using namespace set_term_checks;

CkpdModel model_with(double penalty = 0) {
  return CkpdModel(ckpd::InteractionConstants{1.7e18, -2.3e24, 4.1e30}, penalty, false, 0.01);
}

}  // namespace

TEST_CASE("CKPD bond force is minus the gradient of psi1 and psi1 is C1 L s^2 / 2",
          "[ckpd_model]") {
  std::mt19937 rng(11);
  const CkpdModel model = model_with();
  const TermOf<2> term = [&](const std::vector<Vec3>& X, const std::vector<Vec3>& x) {
    return model.bond_term(X[1] - X[0], x[1] - x[0]);
  };
  for (int trial = 0; trial < 20; ++trial) {
    const std::vector<Vec3> X = random_points(rng, 2, 1e-3), x = strained(rng, X, 3e-5);
    check_forces_are_minus_energy_gradient<2>(term, X, x, 1e-3);
    const double L = (X[1] - X[0]).norm(), l = (x[1] - x[0]).norm(), s = (l - L) / L;
    CHECK(term(X, x).energy == Approx(model.c1 * L * s * s / 2).epsilon(1e-12));
    CHECK(term(X, X).energy == 0);
  }
}

TEST_CASE("CKPD triangle forces are minus the gradient of the triangle's energy", "[ckpd_model]") {
  std::mt19937 rng(12);
  const CkpdModel model = model_with();
  const TermOf<3> term = [&](const std::vector<Vec3>& X, const std::vector<Vec3>& x) {
    const auto P = offsets(X), p = offsets(x);
    return model.triangle_term(P[0], P[1], p[0], p[1], kDegenerate);
  };
  for (int trial = 0; trial < 20; ++trial) {
    const std::vector<Vec3> X = random_points(rng, 3, 1e-3), x = strained(rng, X, 3e-5);
    check_forces_are_minus_energy_gradient<3>(term, X, x, 1e-3);
    // psi2 = C2 A (|a|/A - 1)^2 / 2 per order: the energy per unit weight 2 C2 is psi2 / C2 / 2.
    const auto P = offsets(X), p = offsets(x);
    const double A = P[0].cross(P[1]).norm(), a = p[0].cross(p[1]).norm();
    CHECK(term(X, x).energy == Approx(A * (a / A - 1) * (a / A - 1) / 2).epsilon(1e-9));
  }
}

TEST_CASE("CKPD tetrahedron forces are minus the gradient of its energy, penalty included",
          "[ckpd_model]") {
  std::mt19937 rng(13);
  for (double penalty : {0.0, 1.0}) {
    const CkpdModel model = model_with(penalty);
    const TermOf<4> term = [&](const std::vector<Vec3>& X, const std::vector<Vec3>& x) {
      const auto P = offsets(X), p = offsets(x);
      return model.tetrahedron_term(P[0], P[1], P[2], p[0], p[1], p[2], kDegenerate);
    };
    int inverted = 0;
    for (int trial = 0; trial < 20; ++trial) {
      const std::vector<Vec3> X = random_points(rng, 4, 1e-3);
      std::vector<Vec3> x = strained(rng, X, 3e-5);
      if (trial % 2) std::swap(x[1], x[2]);  // mirror image: inverted
      inverted += term(X, x).inverted;
      check_forces_are_minus_energy_gradient<4>(term, X, x, 1e-3);
    }
    CHECK(inverted >= 8);
  }
}

TEST_CASE("CKPD linearisations equal the finite-difference Jacobians of the set forces",
          "[ckpd_model]") {
  std::mt19937 rng(14);
  const CkpdModel model = model_with();
  for (int trial = 0; trial < 10; ++trial) {
    {
      const std::vector<Vec3> X = random_points(rng, 2, 1e-3);
      const TermOf<2> term = [&](const std::vector<Vec3>& R, const std::vector<Vec3>& x) {
        return model.bond_term(R[1] - R[0], x[1] - x[0]);
      };
      check_linearisation_is_force_jacobian<2>(term, model.bond_linearisation(X[1] - X[0]), X,
                                               1e-3);
    }
    {
      const std::vector<Vec3> X = random_points(rng, 3, 1e-3);
      const TermOf<3> term = [&](const std::vector<Vec3>& R, const std::vector<Vec3>& x) {
        const auto P = offsets(R), p = offsets(x);
        return model.triangle_term(P[0], P[1], p[0], p[1], kDegenerate);
      };
      const auto P = offsets(X);
      check_linearisation_is_force_jacobian<3>(term, model.triangle_linearisation(P[0], P[1]), X,
                                               1e-3);
    }
    {
      const std::vector<Vec3> X = random_points(rng, 4, 1e-3);
      const TermOf<4> term = [&](const std::vector<Vec3>& R, const std::vector<Vec3>& x) {
        const auto P = offsets(R), p = offsets(x);
        return model.tetrahedron_term(P[0], P[1], P[2], p[0], p[1], p[2], kDegenerate);
      };
      const auto P = offsets(X);
      check_linearisation_is_force_jacobian<4>(
          term, model.tetrahedron_linearisation(P[0], P[1], P[2]), X, 1e-3);
    }
  }
}

TEST_CASE("CKPD set forces vanish at the reference state and sum to zero in any state",
          "[ckpd_model]") {
  std::mt19937 rng(15);
  const CkpdModel model = model_with(1.0);
  const std::vector<Vec3> X = random_points(rng, 4, 1e-3), x = strained(rng, X, 5e-5);
  const auto P = offsets(X), p = offsets(x);
  const ckpd::SetTerm<4> at_rest =
      model.tetrahedron_term(P[0], P[1], P[2], P[0], P[1], P[2], kDegenerate);
  const ckpd::SetTerm<4> moved =
      model.tetrahedron_term(P[0], P[1], P[2], p[0], p[1], p[2], kDegenerate);
  Vec3 sum = Vec3::Zero();
  for (int c = 0; c < 4; ++c) {
    CHECK(at_rest.force[c].norm() == 0);
    sum += moved.force[c];
  }
  CHECK(sum.norm() <= 1e-12 * moved.force[0].norm());
  const ckpd::SetTerm<3> tri = model.triangle_term(P[0], P[1], p[0], p[1], kDegenerate);
  CHECK((tri.force[0] + tri.force[1] + tri.force[2]).norm() <= 1e-12 * tri.force[0].norm());
}

TEST_CASE("CKPD value and inverse reference measures give the same law to rounding",
          "[ckpd_model]") {
  const CkpdModel model = model_with(1.0);
  const double V = 3.7e-10, v = -3.9e-10;  // inverted
  const double by_value = model.tetrahedron_coefficient<true>(ckpd::ReferenceMeasure{V}, v, true);
  const double by_inverse =
      model.tetrahedron_coefficient<true>(ckpd::InverseMeasure{1 / V}, v, true);
  CHECK(by_value == Approx(by_inverse).epsilon(1e-15));
  // v/V - sign v + pen3 sign v with pen3 = 2 F |C3| / C3 = 2.
  CHECK(by_value == Approx(v / V + 1 - 2).epsilon(1e-15));
  CHECK(model.tetrahedron_energy_measure(ckpd::ReferenceMeasure{V}, v) ==
        Approx(model.tetrahedron_energy_measure(ckpd::InverseMeasure{1 / V}, v)).epsilon(1e-14));
}

TEST_CASE("CKPD damage rule fails a bond only above the critical stretch", "[ckpd_model]") {
  const CkpdModel model = model_with();
  CHECK(!model.bond_fails(0.01));
  CHECK(model.bond_fails(std::nextafter(0.01, 1.0)));
  CHECK(!model.bond_fails(-0.5));         // compression never fails a bond
  CHECK(!CkpdModel().bond_fails(1e300));  // no critical stretch: no failure
}
