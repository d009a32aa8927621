#pragma once
// Shared by the force-model tests (test_ckpd_model.cpp, test_strain_measure.cpp): random sets,
// and the checks that a set's forces are minus the finite-difference gradient of its energy and
// that its linearisation is the finite-difference Jacobian of its forces.
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "bodies/set_law.hpp"

namespace set_term_checks {

using ckpd::Vec3;

constexpr double kDegenerate = 1e-10;

// A random reference set of n + 1 points around the origin, of size about 1 mm, and a current
// state strained by a few per cent.
inline std::vector<Vec3> random_points(std::mt19937& rng, int count, double scale) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Vec3> x;
  for (int k = 0; k < count; ++k) x.push_back(scale * Vec3(u(rng), u(rng), u(rng)));
  return x;
}

inline std::vector<Vec3> strained(std::mt19937& rng, const std::vector<Vec3>& X, double amount) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Vec3> x = X;
  for (Vec3& p : x) p += amount * Vec3(u(rng), u(rng), u(rng));
  return x;
}

// A family's term as a function of all vertex positions (reference X, current x): forces and
// energy per unit force weight.
template <int N>
using TermOf = std::function<ckpd::SetTerm<N>(const std::vector<Vec3>&, const std::vector<Vec3>&)>;

template <int N>
void check_forces_are_minus_energy_gradient(const TermOf<N>& term, const std::vector<Vec3>& X,
                                            const std::vector<Vec3>& x, double scale) {
  const ckpd::SetTerm<N> t = term(X, x);
  REQUIRE(!t.degenerate);
  const double h = 1e-6 * scale;
  double largest = 0;
  for (int c = 0; c < N; ++c) largest = std::max(largest, t.force[c].norm());
  REQUIRE(largest > 0);
  for (int c = 0; c < N; ++c) {
    for (int d = 0; d < 3; ++d) {
      std::vector<Vec3> plus = x, minus = x;
      plus[c][d] += h;
      minus[c][d] -= h;
      const double gradient = (term(X, plus).energy - term(X, minus).energy) / (2 * h);
      CHECK(std::abs(t.force[c][d] + gradient) <= 1e-6 * largest);
    }
  }
}

template <int N>
void check_linearisation_is_force_jacobian(const TermOf<N>& term,
                                           const ckpd::SetLinearisation<N>& lin,
                                           const std::vector<Vec3>& X, double scale) {
  const double h = 1e-5 * scale;
  double largest = 0;
  for (int c = 0; c < N; ++c)
    for (int d = 0; d < N; ++d) largest = std::max(largest, lin.block(c, d).norm());
  REQUIRE(largest > 0);
  double worst = 0;
  for (int d = 0; d < N; ++d) {
    for (int k = 0; k < 3; ++k) {
      std::vector<Vec3> plus = X, minus = X;
      plus[d][k] += h;
      minus[d][k] -= h;
      const ckpd::SetTerm<N> tp = term(X, plus), tm = term(X, minus);
      for (int c = 0; c < N; ++c) {
        const Vec3 column = (tp.force[c] - tm.force[c]) / (2 * h);
        worst = std::max(worst, (column - lin.block(c, d).col(k)).norm());
      }
    }
  }
  INFO("largest block " << largest << ", worst column difference " << worst);
  CHECK(worst <= 1e-7 * largest);
}

// Offsets of the other vertices from vertex 0.
inline std::vector<Vec3> offsets(const std::vector<Vec3>& x) {
  std::vector<Vec3> o;
  for (std::size_t k = 1; k < x.size(); ++k) o.push_back(x[k] - x[0]);
  return o;
}

}  // namespace set_term_checks
