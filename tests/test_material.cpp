// Elastic and fracture constants (THEORY.md sections 3 and 4).
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "bodies/material.hpp"

namespace {

using ckpd::PlaneMode;
constexpr double pi = std::numbers::pi;

}  // namespace

TEST_CASE("3D constants follow the closed forms of MODEL.md section 3", "[material]") {
  for (const double E : {210e9, 50e9}) {
    for (const double nu : {-0.5, 0.0, 0.1, 0.2, 0.3, 0.45}) {
      for (const double delta : {0.05025, 1.0, 3.015e-3}) {
        INFO("E " << E << ", nu " << nu << ", delta " << delta);
        const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
        const auto c = ckpd::interaction_constants(3, E, nu, PlaneMode::none, delta);
        CHECK(c.c1 == Approx(30 * mu / (pi * std::pow(delta, 4))).epsilon(1e-13));
        CHECK(c.c2 == 0);
        CHECK(c.c3 ==
              Approx(32 * (lambda - mu) / (std::pow(pi, 4) * std::pow(delta, 12))).epsilon(1e-12));
        // C3 < 0 below nu = 1/4, > 0 above.
        CHECK((c.c3 < 0) == (nu < 0.25));
        const auto m = ckpd::elastic_moduli(3, E, nu, PlaneMode::none);
        CHECK(m.lambda == Approx(lambda).epsilon(1e-14).margin(1e-6));
        CHECK(m.mu == Approx(mu).epsilon(1e-14));
        CHECK(m.bulk == Approx(E / (3 * (1 - 2 * nu))).epsilon(1e-14));
      }
    }
  }
}

TEST_CASE("2D plane-stress constants equal the seed's closed forms in E and nu", "[material]") {
  // Seed 001: C1 = 12 E / (pi delta^3 (1 + nu)), C2 = 27/(16 pi delta^6) E (1 - 3 nu)/(nu^2 - 1).
  for (const double nu : {-0.3, 0.0, 0.2, 0.3, 0.4, 0.49}) {
    for (const double delta : {15.075e-3, 9.42e-3, 2.0}) {
      INFO("nu " << nu << ", delta " << delta);
      const double E = 210e9;
      const auto c = ckpd::interaction_constants(2, E, nu, PlaneMode::stress, delta);
      CHECK(c.c1 == Approx(12 * E / (pi * std::pow(delta, 3) * (1 + nu))).epsilon(1e-13));
      CHECK(c.c2 == Approx(27 / (16 * pi * std::pow(delta, 6)) * E * (1 - 3 * nu) / (nu * nu - 1))
                        .epsilon(1e-12));
      CHECK(c.c3 == 0);
      CHECK((c.c2 < 0) == (nu < 1.0 / 3.0));
      const auto m = ckpd::elastic_moduli(2, E, nu, PlaneMode::stress);
      CHECK(m.lambda == Approx(E * nu / (1 - nu * nu)).epsilon(1e-14).margin(1e-6));
      CHECK(m.bulk == Approx(E / (2 * (1 - nu))).epsilon(1e-14));
    }
  }
}

TEST_CASE("2D plane-strain constants use the 3D lambda", "[material]") {
  for (const double nu : {0.1, 0.2, 0.3, 0.4}) {
    INFO("nu " << nu);
    const double E = 190e9, delta = 3.3919e-3;
    const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
    const auto c = ckpd::interaction_constants(2, E, nu, PlaneMode::strain, delta);
    CHECK(c.c1 == Approx(24 * mu / (pi * std::pow(delta, 3))).epsilon(1e-13));
    CHECK(c.c2 == Approx(27 * (lambda - mu) / (8 * pi * std::pow(delta, 6))).epsilon(1e-12));
    CHECK(c.c3 == 0);
    const auto m = ckpd::elastic_moduli(2, E, nu, PlaneMode::strain);
    CHECK(m.bulk == Approx(lambda + mu).epsilon(1e-14));
  }
}

TEST_CASE("constants vanish exactly where lambda equals mu", "[material]") {
  CHECK(ckpd::interaction_constants(3, 210e9, 0.25, PlaneMode::none, 0.01).c3 == 0);
  CHECK(ckpd::interaction_constants(2, 210e9, 1.0 / 3.0, PlaneMode::stress, 0.01).c2 == 0);
  CHECK(ckpd::interaction_constants(2, 210e9, 0.25, PlaneMode::strain, 0.01).c2 == 0);
  // Just off the boundary they do not.
  CHECK(ckpd::interaction_constants(3, 210e9, 0.2501, PlaneMode::none, 0.01).c3 > 0);
  CHECK(ckpd::interaction_constants(2, 210e9, 0.3333, PlaneMode::stress, 0.01).c2 < 0);
}

TEST_CASE("critical stretch follows the Griffith formula of MODEL.md section 4", "[material]") {
  SECTION("3D, hand-computed: mode I 3D steel") {
    // E = 210 GPa, nu = 0.3: G = 210e9/2.6 = 80.76923e9, K = 210e9/1.2 = 175e9;
    // 3G + (3/4)^4 (K - 5G/3) = 242.30769e9 + 0.31640625 * 40.38462e9 = 255.08564e9;
    // s_c = sqrt(500 / (0.05025 * 255.08564e9)) = 1.975031e-4.
    const double sc =
        ckpd::critical_stretch_from_fracture_energy(3, 210e9, 0.3, PlaneMode::none, 0.05025, 500);
    CHECK(sc == Approx(1.975031e-4).epsilon(1e-6));
  }
  SECTION("2D plane stress, hand-computed: mode I 2D steel") {
    // G = 80.76923e9, K = E/(2(1-nu)) = 150e9;
    // 6G/pi + 16/(9 pi^2) (K - 2G) = 154.25844e9 - 2.07896e9 = 152.17948e9;
    // s_c = sqrt(140 / (15.075e-3 * 152.17948e9)) = 2.470343e-4.
    const double sc = ckpd::critical_stretch_from_fracture_energy(2, 210e9, 0.3, PlaneMode::stress,
                                                                  15.075e-3, 140);
    CHECK(sc == Approx(2.470343e-4).epsilon(1e-6));
  }
  SECTION("formula over a range of inputs") {
    for (const double nu : {0.0, 0.2, 0.3, 0.45}) {
      for (const double Gc : {1.0, 140.0, 22000.0}) {
        INFO("nu " << nu << ", Gc " << Gc);
        const double E = 190e9, delta = 3.39e-3, G = E / (2 * (1 + nu));
        const double K3 = E / (3 * (1 - 2 * nu));
        const double s3 = std::sqrt(Gc / (delta * (3 * G + std::pow(0.75, 4) * (K3 - 5 * G / 3))));
        CHECK(ckpd::critical_stretch_from_fracture_energy(3, E, nu, PlaneMode::none, delta, Gc) ==
              Approx(s3).epsilon(1e-13));
        const double Ks = E / (2 * (1 - nu));
        const double Kp = E * nu / ((1 + nu) * (1 - 2 * nu)) + G;
        auto s2 = [&](double K) {
          return std::sqrt(Gc / (delta * (6 * G / pi + 16 / (9 * pi * pi) * (K - 2 * G))));
        };
        CHECK(ckpd::critical_stretch_from_fracture_energy(2, E, nu, PlaneMode::stress, delta, Gc) ==
              Approx(s2(Ks)).epsilon(1e-13));
        CHECK(ckpd::critical_stretch_from_fracture_energy(2, E, nu, PlaneMode::strain, delta, Gc) ==
              Approx(s2(Kp)).epsilon(1e-13));
      }
    }
  }
}

TEST_CASE("invalid elastic inputs throw std::invalid_argument", "[material]") {
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Bad {
    int dimension;
    double E, nu;
    PlaneMode plane;
  };
  const std::vector<Bad> bad = {
      {3, 0.0, 0.3, PlaneMode::none},      {3, -1e9, 0.3, PlaneMode::none},
      {3, nan, 0.3, PlaneMode::none},      {3, inf, 0.3, PlaneMode::none},
      {3, 210e9, 0.5, PlaneMode::none},    {3, 210e9, 0.7, PlaneMode::none},
      {3, 210e9, -1.0, PlaneMode::none},   {3, 210e9, -1.5, PlaneMode::none},
      {3, 210e9, nan, PlaneMode::none},    {3, 210e9, 0.3, PlaneMode::stress},
      {3, 210e9, 0.3, PlaneMode::strain},  {2, 210e9, 0.3, PlaneMode::none},
      {2, 210e9, 0.5, PlaneMode::stress},  {2, 0.0, 0.3, PlaneMode::strain},
      {2, 210e9, -1.0, PlaneMode::stress}, {1, 210e9, 0.3, PlaneMode::none},
      {4, 210e9, 0.3, PlaneMode::none},
  };
  for (const Bad& b : bad) {
    INFO("dimension " << b.dimension << ", E " << b.E << ", nu " << b.nu << ", plane "
                      << ckpd::to_string(b.plane));
    CHECK_THROWS_AS(ckpd::check_elastic_input(b.dimension, b.E, b.nu, b.plane),
                    std::invalid_argument);
    CHECK_THROWS_AS(ckpd::elastic_moduli(b.dimension, b.E, b.nu, b.plane), std::invalid_argument);
    CHECK_THROWS_AS(ckpd::interaction_constants(b.dimension, b.E, b.nu, b.plane, 0.01),
                    std::invalid_argument);
    CHECK_THROWS_AS(
        ckpd::critical_stretch_from_fracture_energy(b.dimension, b.E, b.nu, b.plane, 0.01, 100),
        std::invalid_argument);
  }
  // Just inside the valid range: no throw.
  CHECK_NOTHROW(ckpd::check_elastic_input(3, 1.0, 0.499, PlaneMode::none));
  CHECK_NOTHROW(ckpd::check_elastic_input(3, 1.0, -0.999, PlaneMode::none));
  CHECK_NOTHROW(ckpd::check_elastic_input(2, 1.0, 0.3, PlaneMode::stress));
  CHECK_NOTHROW(ckpd::check_elastic_input(2, 1.0, 0.3, PlaneMode::strain));
}

TEST_CASE("invalid horizon, fracture energy and plane-mode names throw", "[material]") {
  CHECK_THROWS_AS(ckpd::interaction_constants(3, 210e9, 0.3, PlaneMode::none, 0.0),
                  std::invalid_argument);
  CHECK_THROWS_AS(ckpd::interaction_constants(3, 210e9, 0.3, PlaneMode::none, -1.0),
                  std::invalid_argument);
  CHECK_THROWS_AS(
      ckpd::critical_stretch_from_fracture_energy(3, 210e9, 0.3, PlaneMode::none, 0.0, 100),
      std::invalid_argument);
  for (const double Gc : {0.0, -1.0, std::numeric_limits<double>::infinity()}) {
    CHECK_THROWS_AS(
        ckpd::critical_stretch_from_fracture_energy(3, 210e9, 0.3, PlaneMode::none, 0.01, Gc),
        std::invalid_argument);
  }
  CHECK(ckpd::plane_mode_from_string("stress") == PlaneMode::stress);
  CHECK(ckpd::plane_mode_from_string("strain") == PlaneMode::strain);
  CHECK(ckpd::to_string(PlaneMode::stress) == "stress");
  CHECK(ckpd::to_string(PlaneMode::strain) == "strain");
  CHECK_THROWS_AS(ckpd::plane_mode_from_string("Stress"), std::invalid_argument);
  CHECK_THROWS_AS(ckpd::plane_mode_from_string(""), std::invalid_argument);
}
