#include "bodies/material.hpp"

#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace ckpd {

PlaneMode plane_mode_from_string(const std::string& name) {
  if (name == "stress") return PlaneMode::stress;
  if (name == "strain") return PlaneMode::strain;
  throw std::invalid_argument("expected 'stress' or 'strain', got '" + name + "'");
}

std::string to_string(PlaneMode mode) {
  switch (mode) {
    case PlaneMode::stress:
      return "stress";
    case PlaneMode::strain:
      return "strain";
    default:
      return "none";
  }
}

void check_elastic_input(int dimension, double youngs_modulus, double poisson_ratio,
                         PlaneMode plane) {
  std::ostringstream msg;
  if (dimension != 2 && dimension != 3) {
    msg << "dimension must be 2 or 3, got " << dimension;
  } else if (!(youngs_modulus > 0) || !std::isfinite(youngs_modulus)) {
    msg << "Young's modulus must be positive and finite, got " << youngs_modulus;
  } else if (!(poisson_ratio > -1.0 && poisson_ratio < 0.5)) {
    msg << "Poisson's ratio must lie in (-1, 0.5), got " << poisson_ratio;
  } else if (dimension == 3 && plane != PlaneMode::none) {
    msg << "plane stress/strain applies to 2D bodies only";
  } else if (dimension == 2 && plane == PlaneMode::none) {
    msg << "a 2D body needs plane stress or plane strain";
  } else {
    return;
  }
  throw std::invalid_argument(msg.str());
}

ElasticModuli elastic_moduli(int dimension, double E, double nu, PlaneMode plane) {
  check_elastic_input(dimension, E, nu, plane);
  const double mu = E / (2 * (1 + nu));
  if (dimension == 3) {
    return {E * nu / ((1 + nu) * (1 - 2 * nu)), mu, E / (3 * (1 - 2 * nu))};
  }
  if (plane == PlaneMode::stress) {
    const double lambda_star = E * nu / (1 - nu * nu);
    return {lambda_star, mu, E / (2 * (1 - nu))};
  }
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  return {lambda, mu, lambda + mu};
}

InteractionConstants interaction_constants(int dimension, double E, double nu, PlaneMode plane,
                                           double horizon) {
  if (!(horizon > 0)) throw std::invalid_argument("horizon must be positive");
  const ElasticModuli m = elastic_moduli(dimension, E, nu, plane);
  const double pi = std::numbers::pi;
  InteractionConstants c;
  if (dimension == 3) {
    c.c1 = 30 * m.mu / (pi * std::pow(horizon, 4));
    c.c3 = 32 * (m.lambda - m.mu) / (std::pow(pi, 4) * std::pow(horizon, 12));
  } else {
    c.c1 = 24 * m.mu / (pi * std::pow(horizon, 3));
    c.c2 = 27 * (m.lambda - m.mu) / (8 * pi * std::pow(horizon, 6));
  }
  // lambda == mu (nu = 1/4 in 3D, 1/3 in plane stress) must give exactly zero so that the
  // family is skipped; the subtraction above is exact only when both round the same way.
  if (std::abs(m.lambda - m.mu) <= 1e-12 * m.mu) c.c2 = c.c3 = 0;
  return c;
}

double critical_stretch_from_fracture_energy(int dimension, double E, double nu, PlaneMode plane,
                                             double horizon, double Gc) {
  if (!(Gc > 0) || !std::isfinite(Gc))
    throw std::invalid_argument("fracture energy must be positive and finite");
  if (!(horizon > 0)) throw std::invalid_argument("horizon must be positive");
  const ElasticModuli m = elastic_moduli(dimension, E, nu, plane);
  const double G = m.mu, K = m.bulk, pi = std::numbers::pi;
  const double stiffness = dimension == 3 ? 3 * G + std::pow(0.75, 4) * (K - 5 * G / 3)
                                          : 6 * G / pi + 16 / (9 * pi * pi) * (K - 2 * G);
  if (!(stiffness > 0))
    throw std::invalid_argument(
        "the Griffith critical-stretch formula has no real solution for "
        "this E, nu (its stiffness term is not positive); give "
        "critical_stretch directly");
  return std::sqrt(Gc / (horizon * stiffness));
}

}  // namespace ckpd
