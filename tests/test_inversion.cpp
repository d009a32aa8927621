// Model breakdown under extreme compression: inverted tetrahedra (3D) and triangles (2D) are
// counted, and the optional inversion penalty (Body::inversion_penalty) adds 2 F |C| |v| per
// inverted ordered set, consistently in the reference and the symmetric kernel.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "bodies/material.hpp"
#include "bodies/symmetric_kernel.hpp"
#include "body_fixtures.hpp"
#include "reference/internal_force.hpp"

namespace {

using ckpd::Body;
using ckpd::PlaneMode;
using ckpd::Vec3;
using namespace ckpd_test;

constexpr double kE = 210e9;
constexpr double kDx = 1e-3;

ckpd::BodyDefinition block(int dimension, double nu, double m, int n) {
  const PlaneMode plane = dimension == 2 ? PlaneMode::stress : PlaneMode::none;
  const auto c = ckpd::interaction_constants(dimension, kE, nu, plane, m * kDx);
  return lattice_block(dimension, n, n, dimension == 3 ? n : 1, kDx, m, c, 7850);
}

struct Evaluation {
  std::vector<Vec3> force;
  std::vector<double> energy;
  std::uint64_t inverted = 0;  // reference: per point own family; symmetric: each set once
};

Evaluation reference(Body& body) {
  ckpd::compute_internal_force(body, true);
  Evaluation e{body.force_density, body.strain_energy_density, 0};
  ckpd::FamilyScratch scratch;
  for (std::size_t i = 0; i < body.size(); ++i)
    e.inverted += ckpd::evaluate_point(body, i, scratch).inverted;
  return e;
}

Evaluation symmetric(Body& body) {
  const ckpd::SymmetricKernelStats s = ckpd::compute_internal_force_symmetric(body, true);
  return {body.force_density, body.strain_energy_density,
          s.inverted_tetrahedra + s.inverted_triangles};
}

// Largest force and energy differences, relative to the largest value of either.
std::pair<double, double> difference(const Evaluation& a, const Evaluation& b) {
  double fs = 0, es = 0, fd = 0, ed = 0;
  for (std::size_t i = 0; i < a.force.size(); ++i) {
    fs = std::max({fs, a.force[i].norm(), b.force[i].norm()});
    es = std::max({es, std::abs(a.energy[i]), std::abs(b.energy[i])});
    fd = std::max(fd, (a.force[i] - b.force[i]).norm());
    ed = std::max(ed, std::abs(a.energy[i] - b.energy[i]));
  }
  return {fd / fs, ed / es};
}

struct Case {
  std::string label;
  ckpd::BodyDefinition definition;
  int vertices;  // per set: 4 tetrahedron, 3 triangle
};

std::vector<Case> cases() {
  return {{"3D nu=0.3 (C3>0)", block(3, 0.3, 2.015, 5), 4},
          {"3D nu=0.05 (C3<0)", block(3, 0.05, 2.015, 5), 4},
          {"2D nu=0.2 (C2<0)", block(2, 0.2, 3.015, 8), 3},
          {"2D nu=0.45 (C2>0)", block(2, 0.45, 3.015, 8), 3}};
}

}  // namespace

TEST_CASE("inverted sets are counted alike by the reference and the symmetric kernel",
          "[stability]") {
  std::mt19937 rng(808);
  for (const Case& c : cases()) {
    SECTION(c.label) {
      Body body = ckpd::make_body(c.definition);
      perturb(body, 0.7 * kDx, rng);  // large enough that many sets turn inside out
      const Evaluation r = reference(body), s = symmetric(body);
      REQUIRE(s.inverted > 0);
      // An undamaged lattice's sets are non-degenerate from every vertex: each is in the
      // families of all its vertices.
      CHECK(r.inverted == c.vertices * s.inverted);
    }
  }
}

TEST_CASE("no set is inverted under small or rigid motion", "[stability]") {
  std::mt19937 rng(9);
  for (const Case& c : cases()) {
    SECTION(c.label) {
      Body body = ckpd::make_body(c.definition);
      perturb(body, 0.05 * kDx, rng);
      CHECK(symmetric(body).inverted == 0);
      // A half turn about z keeps every orientation (about x it would too in 3D).
      for (std::size_t i = 0; i < body.size(); ++i) {
        const Vec3 X = body.reference_position[i];
        body.displacement[i] = Vec3(-X.x(), -X.y(), X.z()) - X;
      }
      CHECK(symmetric(body).inverted == 0);
      CHECK(reference(body).inverted == 0);
    }
  }
}

TEST_CASE("inversion penalty: symmetric kernel equals the reference kernel", "[stability]") {
  std::mt19937 rng(4242);
  for (const Case& c : cases()) {
    for (double penalty : {1.0, 3.5}) {
      SECTION(c.label + ", penalty " + std::to_string(penalty)) {
        ckpd::BodyDefinition d = c.definition;
        d.inversion_penalty = penalty;
        Body body = ckpd::make_body(d);
        perturb(body, 0.7 * kDx, rng);
        std::mt19937 damage(1);
        fail_random_bonds(body, 0.05, damage);
        body.damage_enabled = true;
        const Evaluation r = reference(body), s = symmetric(body);
        REQUIRE(s.inverted > 0);
        const auto [fd, ed] = difference(r, s);
        CHECK(fd <= 1e-12);
        CHECK(ed <= 1e-12);
        // And the penalty changed the result (the comparison is not of two unpenalised runs).
        d.inversion_penalty = 0;
        Body plain = ckpd::make_body(d);
        plain.displacement = body.displacement;
        plain.bond_intact = body.bond_intact;
        plain.damage_enabled = true;
        const auto [pf, pe] = difference(symmetric(plain), s);
        CHECK(pf > 1e-3);
        CHECK(pe > 1e-3);
      }
    }
  }
}

TEST_CASE("inversion penalty force is minus the gradient of the own-family energy", "[stability]") {
  std::mt19937 rng(77);
  for (const Case& c : cases()) {
    SECTION(c.label) {
      ckpd::BodyDefinition d = c.definition;
      d.inversion_penalty = 2;
      Body body = ckpd::make_body(d);
      perturb(body, 0.6 * kDx, rng);
      ckpd::FamilyScratch scratch;
      std::uint64_t inverted = 0;
      double scale = 0;
      std::vector<Vec3> force(body.size());
      for (std::size_t i = 0; i < body.size(); ++i) {
        const ckpd::PointResult r = ckpd::evaluate_point(body, i, scratch);
        force[i] = r.force_density;
        inverted += r.inverted;
        scale = std::max(scale, force[i].norm());
      }
      REQUIRE(inverted > 0);
      auto energy = [&](std::size_t i) {
        const ckpd::PointResult r = ckpd::evaluate_point(body, i, scratch);
        return r.w1 + r.w2 + r.w3;
      };
      // The energy has kinks where some v = 0; a step of 1e-9 dx crosses one only if some set
      // is that close to flat, which the reported worst value would show.
      const double h = 1e-9 * kDx;
      double worst = 0;
      for (std::size_t i = 0; i < body.size(); ++i) {
        for (int k = 0; k < body.dimension; ++k) {
          const double saved = body.displacement[i][k];
          body.displacement[i][k] = saved + h;
          const double plus = energy(i);
          body.displacement[i][k] = saved - h;
          const double minus = energy(i);
          body.displacement[i][k] = saved;
          worst = std::max(worst, std::abs(force[i][k] + (plus - minus) / (2 * h)) / scale);
        }
      }
      INFO("largest |b + dW/dx| relative to the largest force: " << worst);
      CHECK(worst < 1e-5);
    }
  }
}

TEST_CASE("inversion penalty does nothing to a configuration without inverted sets",
          "[stability]") {
  std::mt19937 rng(31);
  for (const Case& c : cases()) {
    SECTION(c.label) {
      ckpd::BodyDefinition d = c.definition;
      Body plain = ckpd::make_body(d);
      d.inversion_penalty = 5;
      Body penalised = ckpd::make_body(d);
      perturb(plain, 0.1 * kDx, rng);  // 10 % strains, nothing inverted
      penalised.displacement = plain.displacement;
      const Evaluation a = symmetric(plain), b = symmetric(penalised);
      REQUIRE(a.inverted == 0);
      CHECK(a.force == b.force);
      CHECK(a.energy == b.energy);
      const Evaluation ra = reference(plain), rb = reference(penalised);
      CHECK(ra.force == rb.force);
      CHECK(ra.energy == rb.energy);
    }
  }
}

TEST_CASE("inversion penalty 1 makes a tetrahedron's energy smooth through zero volume",
          "[stability]") {
  // One tetrahedron (all six edges within the horizon); its apex is pushed through the base.
  const auto c = ckpd::interaction_constants(3, kE, 0.3, PlaneMode::none, 3 * kDx);
  auto energy_at = [&](double penalty, double apex_z) {
    ckpd::BodyDefinition d;
    d.name = "tet";
    d.density = 1;
    d.horizon = 3 * kDx;
    d.constants = c;
    d.reference_position = {Vec3(0, 0, 0), Vec3(kDx, 0, 0), Vec3(0, kDx, 0), Vec3(0, 0, kDx)};
    d.volume.assign(4, kDx * kDx * kDx);
    d.full_family_volume = 4 * kDx * kDx * kDx;
    d.inversion_penalty = penalty;
    Body body = ckpd::make_body(d);
    body.displacement[3] = Vec3(0.2 * kDx, 0.1 * kDx, apex_z - kDx);
    const ckpd::SymmetricKernelStats s = ckpd::compute_internal_force_symmetric(body, true);
    double e = 0;
    for (std::size_t i = 0; i < 4; ++i) e += body.strain_energy_density[i] * body.volume[i];
    return std::pair{e, s.inverted_tetrahedra};
  };
  const double h = 1e-6 * kDx;
  for (double penalty : {0.0, 1.0}) {
    const auto [below, inverted] = energy_at(penalty, -h);
    const auto [flat, none0] = energy_at(penalty, 0);
    const auto [above, none1] = energy_at(penalty, h);
    CHECK(inverted == 1);
    CHECK(none0 + none1 == 0);
    const double left = (flat - below) / h, right = (above - flat) / h;
    INFO("penalty " << penalty << ": slope below " << left << ", above " << right);
    if (penalty == 0) {
      // |v|: the energy peaks at zero volume, and an inverted tetrahedron is pushed on.
      CHECK(left > 0);
      CHECK(right < 0);
    } else {
      // The signed volume's energy: one slope (to the bonds' curvature over 2 h), still falling
      // as the apex rises (the tetrahedron is pushed back up).
      CHECK(std::abs(left - right) < 1e-2 * std::abs(left));
      CHECK(left < 0);
    }
    // The penalty's energy is 3 F |C3| dV3 |v| per vertex (6 orders x 2 F |C3| |v|, W3 / 4).
    if (penalty == 1) {
      const auto [deep_plain, n0] = energy_at(0, -0.3 * kDx);
      const auto [deep_pen, n1] = energy_at(1, -0.3 * kDx);
      ckpd::BodyDefinition d;
      Body probe = [&] {
        d.name = "tet";
        d.density = 1;
        d.horizon = 3 * kDx;
        d.constants = c;
        d.reference_position = {Vec3(0, 0, 0), Vec3(kDx, 0, 0), Vec3(0, kDx, 0), Vec3(0, 0, kDx)};
        d.volume.assign(4, kDx * kDx * kDx);
        d.full_family_volume = 4 * kDx * kDx * kDx;
        return ckpd::make_body(d);
      }();
      const double v = 0.3 * kDx * kDx * kDx;  // |v| of the inverted tetrahedron (base kDx^2)
      double expected = 0;
      for (std::size_t i = 0; i < 4; ++i)
        expected += probe.volume[i] * 3 * std::abs(c.c3) * probe.dv3[i] * v;
      CHECK(n0 == 1);
      CHECK(n1 == 1);
      CHECK(deep_pen - deep_plain == Approx(expected).epsilon(1e-10));
    }
  }
}

TEST_CASE("inversion penalty needs the family it acts on", "[stability]") {
  ckpd::BodyDefinition d = block(3, 0.25, 2.015, 3);  // C3 = 0: no tetrahedra
  d.inversion_penalty = 1;
  CHECK_THROWS_WITH(ckpd::make_body(d), Catch::Contains("three-neighbour"));
  d = block(3, 0.3, 2.015, 3);
  d.inversion_penalty = -1;
  CHECK_THROWS_WITH(ckpd::make_body(d), Catch::Contains("inversion penalty"));
}
