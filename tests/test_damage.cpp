// Bond failure, point damage, d2/d3, no-failure zones and pre-cracks (THEORY.md section 4).
#include <Eigen/Geometry>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

#include "bodies/damage.hpp"
#include "bodies/material.hpp"
#include "body_fixtures.hpp"
#include "reference/internal_force.hpp"
#include "reference_kernel.hpp"

namespace {

using ckpd::Body;
using ckpd::Precrack;
using ckpd::Vec3;
using namespace ckpd_test;

bool intact(const Body& body, std::size_t i, std::size_t j) {
  return body.bond_intact[static_cast<std::size_t>(bond_slot(body, i, j))] != 0;
}

// Two points one unit apart: one bond.
Body two_point_body(double critical_stretch) {
  ckpd::BodyDefinition d;
  d.name = "pair";
  d.dimension = 2;
  d.reference_position = {Vec3(0, 0, 0), Vec3(1, 0, 0)};
  d.volume = {1, 1};
  d.density = 1;
  d.horizon = 1.5;
  d.constants = {1, 0, 0};
  d.critical_stretch = critical_stretch;
  d.full_family_volume = 1;
  return ckpd::make_body(d);
}

}  // namespace

TEST_CASE("a bond stretched past the critical stretch fails and stays failed", "[damage]") {
  const double sc = 0.01;
  Body body = two_point_body(sc);
  REQUIRE(body.damage_enabled);
  REQUIRE(body.bond_count() == 1);

  body.displacement[1] = Vec3(0.0099, 0, 0);  // s = 0.99 s_c
  CHECK(ckpd::update_bond_failure(body) == 0);
  body.displacement[1] = Vec3(-0.5, 0, 0);  // compression never breaks a bond
  CHECK(ckpd::update_bond_failure(body) == 0);
  CHECK(ckpd::failed_bond_count(body) == 0);

  body.displacement[1] = Vec3(0.0101, 0, 0);  // s = 1.01 s_c
  CHECK(ckpd::update_bond_failure(body) == 1);
  CHECK_FALSE(intact(body, 0, 1));  // both stored directions
  CHECK_FALSE(intact(body, 1, 0));
  CHECK(ckpd::failed_bond_count(body) == 1);

  body.displacement[1] = Vec3::Zero();  // unloaded: still failed, and not counted again
  CHECK(ckpd::update_bond_failure(body) == 0);
  CHECK_FALSE(intact(body, 0, 1));
  CHECK(ckpd::failed_bond_count(body) == 1);

  // A failed bond carries no force, even when stretched again.
  body.displacement[1] = Vec3(0.3, 0, 0);
  ckpd::compute_internal_force(body, true);
  CHECK(body.force_density[0].norm() == 0);
  CHECK(body.strain_energy_density[0] == 0);
}

TEST_CASE("without a critical stretch no bond ever fails", "[damage]") {
  Body body = two_point_body(std::numeric_limits<double>::infinity());
  CHECK_FALSE(body.damage_enabled);
  body.displacement[1] = Vec3(10, 0, 0);
  CHECK(ckpd::update_bond_failure(body) == 0);
  ckpd::compute_internal_force(body, false);
  CHECK(body.force_density[0].x() > 0);  // the bond pulls point 0 towards point 1
}

TEST_CASE("both stored directions of a bond fail together under random loads", "[damage]") {
  std::mt19937 rng(17);
  const auto d0 = jittered_cloud(3, 6, 6, 5, 1.0, 2.2, {1, 0, 0}, 0.3, rng);
  ckpd::BodyDefinition d = d0;
  d.critical_stretch = 0.02;
  Body body = ckpd::make_body(d);
  perturb(body, 0.05, rng);
  const std::size_t failed = ckpd::update_bond_failure(body);
  REQUIRE(failed > 0);
  REQUIRE(failed < body.bond_count());
  CHECK(ckpd::failed_bond_count(body) == failed);
  for (std::size_t i = 0; i < body.size(); ++i) {
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k) {
      const std::size_t j = body.family.neighbour[k];
      CHECK(intact(body, i, j) == intact(body, j, i));
      // Failed exactly when the objective stretch (l - L)/L exceeds s_c.
      const Vec3 dX = body.reference_position[j] - body.reference_position[i];
      const Vec3 dx = dX + body.displacement[j] - body.displacement[i];
      CHECK(intact(body, i, j) == !((dx.norm() - dX.norm()) / dX.norm() > 0.02));
    }
  }
}

TEST_CASE("bonds touching no-failure points survive a stretch that breaks the others", "[damage]") {
  ckpd::BodyDefinition d = lattice_block(2, 6, 5, 1, 1.0, 1.5, {1, 0, 0});
  d.critical_stretch = 0.01;
  d.no_failure.assign(d.reference_position.size(), 0);
  for (std::size_t i = 0; i < d.reference_position.size(); ++i)
    if (d.reference_position[i].x() == 0 ||
        (d.reference_position[i].x() == 4 && d.reference_position[i].y() == 2))
      d.no_failure[i] = 1;
  Body body = ckpd::make_body(d);
  for (std::size_t i = 0; i < body.size(); ++i)
    body.displacement[i] = 0.02 * body.reference_position[i];  // every bond stretched by 2 s_c
  const std::size_t failed = ckpd::update_bond_failure(body);
  std::size_t protected_bonds = 0;
  for (std::size_t i = 0; i < body.size(); ++i) {
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k) {
      const std::size_t j = body.family.neighbour[k];
      const bool shielded = body.no_failure[i] || body.no_failure[j];
      CHECK(intact(body, i, j) == shielded);
      protected_bonds += shielded && i < j;
    }
  }
  CHECK(protected_bonds > 0);
  CHECK(failed == body.bond_count() - protected_bonds);
}

TEST_CASE("point damage is the failed fraction of a point's bonds", "[damage]") {
  // 3 x 3 square lattice, horizon 1.5: the centre (index 4) has 8 bonds, an edge midpoint 5,
  // a corner 3.
  ckpd::BodyDefinition d = lattice_block(2, 3, 3, 1, 1.0, 1.5, {1, 0, 0});
  d.critical_stretch = 0.1;
  Body body = ckpd::make_body(d);
  REQUIRE(body.family.family_size(4) == 8);
  REQUIRE(body.family.family_size(0) == 3);
  REQUIRE(body.family.family_size(5) == 5);
  std::vector<double> damage;
  ckpd::point_damage(body, damage);
  for (double x : damage) CHECK(x == 0);
  fail_bond(body, 4, 0);  // centre - corner (0, 0)
  fail_bond(body, 4, 5);  // centre - edge point (2, 1)
  ckpd::point_damage(body, damage);
  CHECK(damage[4] == Approx(2.0 / 8.0));
  CHECK(damage[0] == Approx(1.0 / 3.0));
  CHECK(damage[5] == Approx(1.0 / 5.0));
  for (std::size_t i : {1, 2, 3, 6, 7, 8}) CHECK(damage[i] == 0);
  CHECK(ckpd::max_point_damage(body) == Approx(1.0 / 3.0));
  CHECK(ckpd::failed_bond_count(body) == 2);
}

TEST_CASE("a failed bond removes every pair and triple through it from the centre's sums",
          "[damage]") {
  std::mt19937 rng(23);
  struct Case {
    const char* label;
    ckpd::BodyDefinition definition;
  };
  const std::vector<Case> cases = {
      {"2D, two-neighbour",
       lattice_block(2, 7, 7, 1, 1.0, 3.015,
                     ckpd::interaction_constants(2, 1.0, 0.2, ckpd::PlaneMode::stress, 3.015))},
      {"3D, three-neighbour",
       lattice_block(3, 5, 5, 5, 1.0, 2.015,
                     ckpd::interaction_constants(3, 1.0, 0.35, ckpd::PlaneMode::none, 2.015))},
  };
  for (const Case& c : cases) {
    INFO(c.label);
    ckpd::BodyDefinition d = c.definition;
    d.critical_stretch = 10;  // bookkeeping on; nothing fails by stretch here
    d.constants.c1 = 0;       // only pairs (2D) or triples (3D) couple the points
    Body body = ckpd::make_body(d);
    perturb(body, 0.02, rng);
    ckpd::FamilyScratch scratch;
    const std::size_t i = body.size() / 2;  // the centre point
    const std::size_t j = body.family.neighbour[body.family.offset[i] + 3];
    auto result = [&](std::size_t p) { return ckpd::evaluate_point(body, p, scratch); };
    const Vec3 kick(0.3, -0.2, d.dimension == 3 ? 0.25 : 0);
    auto force_change = [&](std::size_t p, std::size_t moved) {
      const ckpd::PointResult r0 = result(p);
      body.displacement[moved] += kick;
      const ckpd::PointResult r1 = result(p);
      body.displacement[moved] -= kick;
      return (r1.force_density - r0.force_density).norm() / r0.force_density.norm() +
             std::abs(r1.w1 + r1.w2 + r1.w3 - (r0.w1 + r0.w2 + r0.w3)) /
                 std::abs(r0.w1 + r0.w2 + r0.w3);
    };
    // With the bond intact, moving j changes i's force and energy through the pairs or triples
    // that contain j, and vice versa (control).
    const ckpd::PointResult before = result(i);
    CHECK(force_change(i, j) > 1e-3);
    CHECK(force_change(j, i) > 1e-3);

    fail_bond(body, i, j);
    const ckpd::PointResult cut = result(i);
    // Now i's force and energy do not depend on x^j at all, nor j's on x^i: every pair and
    // triple of i that contains j contains the failed bond i-j (d2, d3 = 0).
    CHECK(force_change(i, j) <= 1e-14);
    CHECK(force_change(j, i) <= 1e-14);
    // Other neighbours still act on i.
    const std::size_t k = body.family.neighbour[body.family.offset[i] + 5];
    CHECK(force_change(i, k) > 1e-3);

    // And i's sums are the ordered reference with d2, d3 from the intact flags.
    const ReferenceResult ref = reference_point(body, i);
    CHECK((cut.force_density - ref.force()).norm() <= 1e-12 * ref.force().norm());
    CHECK(cut.w1 + cut.w2 + cut.w3 == Approx(ref.energy()).epsilon(1e-12));
    // The failure changed both the force and the energy of i.
    CHECK((cut.force_density - before.force_density).norm() > 1e-3 * before.force_density.norm());
  }
}

TEST_CASE("d2 and d3 depend only on the centre's bonds: a failed bond j-k leaves i's sums alone",
          "[damage]") {
  std::mt19937 rng(29);
  for (const int dimension : {2, 3}) {
    INFO("dimension " << dimension);
    const double m = dimension == 3 ? 2.015 : 3.015;
    ckpd::BodyDefinition d =
        lattice_block(dimension, 5, 5, dimension == 3 ? 5 : 1, 1.0, m,
                      ckpd::interaction_constants(
                          dimension, 1.0, 0.4,
                          dimension == 3 ? ckpd::PlaneMode::none : ckpd::PlaneMode::stress, m));
    d.critical_stretch = 10;
    Body body = ckpd::make_body(d);
    perturb(body, 0.02, rng);
    ckpd::FamilyScratch scratch;
    const std::size_t i = body.size() / 2;
    const ckpd::PointResult before = ckpd::evaluate_point(body, i, scratch);
    // Fail every bond between two members of i's family (none of i's own bonds).
    std::size_t failed = 0;
    for (std::size_t a = body.family.offset[i]; a < body.family.offset[i + 1]; ++a)
      for (std::size_t b = a + 1; b < body.family.offset[i + 1]; ++b) {
        const std::size_t j = body.family.neighbour[a], k = body.family.neighbour[b];
        if (bond_slot(body, j, k) >= 0) {
          fail_bond(body, j, k);
          ++failed;
        }
      }
    REQUIRE(failed > 0);
    const ckpd::PointResult after = ckpd::evaluate_point(body, i, scratch);
    CHECK(after.force_density == before.force_density);
    CHECK(after.w1 == before.w1);
    CHECK(after.w2 == before.w2);
    CHECK(after.w3 == before.w3);
    const ReferenceResult ref = reference_point(body, i);
    CHECK((after.force_density - ref.force()).norm() <= 1e-12 * ref.force().norm());
  }
}

namespace {

// Independent crossing tests for the pre-crack rule: the bond's end points lie strictly on
// opposite sides of the crack's line (2D) or plane (3D), and the crossing point lies inside
// the segment or convex polygon (edges included).
bool crosses_segment_2d(const Vec3& a, const Vec3& b, const Vec3& c0, const Vec3& c1) {
  const Vec3 t = c1 - c0;
  auto side = [&](const Vec3& p) { return t.x() * (p - c0).y() - t.y() * (p - c0).x(); };
  const double sa = side(a), sb = side(b);
  if (!((sa > 0 && sb < 0) || (sa < 0 && sb > 0))) return false;
  const Vec3 x = a + (b - a) * (sa / (sa - sb));
  const double s = (x - c0).dot(t) / t.squaredNorm();
  return s >= 0 && s <= 1;
}

bool crosses_polygon_3d(const Vec3& a, const Vec3& b, const std::vector<Vec3>& c) {
  const Vec3 n = (c[1] - c[0]).cross(c[2] - c[0]);
  const double da = n.dot(a - c[0]), db = n.dot(b - c[0]);
  if (!((da > 0 && db < 0) || (da < 0 && db > 0))) return false;
  const Vec3 x = a + (b - a) * (da / (da - db));
  for (std::size_t k = 0; k < c.size(); ++k) {
    const Vec3 edge = c[(k + 1) % c.size()] - c[k];
    if (n.dot(edge.cross(x - c[k])) < 0) return false;  // corners listed counter-clockwise
  }
  return true;
}

void check_precrack(ckpd::BodyDefinition d, const Precrack& crack, bool three_d) {
  auto expected_cut = [&](const Vec3& a, const Vec3& b) {
    return three_d ? crosses_polygon_3d(a, b, crack.corners)
                   : crosses_segment_2d(a, b, crack.corners[0], crack.corners[1]);
  };
  Body fresh = ckpd::make_body(d);
  const std::size_t cut = ckpd::apply_precrack(fresh, crack);
  d.precracks = {crack};
  const Body body = ckpd::make_body(d);
  std::size_t expected = 0;
  for (std::size_t i = 0; i < body.size(); ++i) {
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k) {
      const std::size_t j = body.family.neighbour[k];
      const bool crosses = expected_cut(body.reference_position[i], body.reference_position[j]);
      CHECK(body.bond_intact[k] == !crosses);
      CHECK(fresh.bond_intact[k] == !crosses);
      expected += crosses && i < j;
    }
  }
  CHECK(expected > 0);
  CHECK(expected < body.bond_count());
  CHECK(cut == expected);
  CHECK(ckpd::failed_bond_count(body) == expected);
  // Applying it again cuts nothing new.
  CHECK(ckpd::apply_precrack(fresh, crack) == 0);
}

}  // namespace

TEST_CASE("a pre-crack cuts exactly the bonds that cross it", "[damage]") {
  std::mt19937 rng(31);
  SECTION("2D segment, lattice and jittered cloud") {
    const Precrack crack{{Vec3(-0.5, 5.43, 0), Vec3(6.71, 5.52, 0)}};
    check_precrack(lattice_block(2, 12, 12, 1, 1.0, 3.015, {1, 0, 0}), crack, false);
    check_precrack(jittered_cloud(2, 12, 12, 1, 1.0, 3.015, {1, 0, 0}, 0.3, rng), crack, false);
    // A crack ending in the middle of the body, in the other direction.
    check_precrack(jittered_cloud(2, 12, 12, 1, 1.0, 2.5, {1, 0, 0}, 0.3, rng),
                   Precrack{{Vec3(7.3, 12.5, 0), Vec3(6.1, 4.2, 0)}}, false);
  }
  SECTION("3D planar polygons, lattice and jittered cloud") {
    // A tilted quadrilateral (plane z = 2.4 + 0.2 (x+1)/6.3 + 0.1 (y+1)/9.2) reaching half way.
    const Precrack quad{
        {Vec3(-1, -1, 2.4), Vec3(5.3, -1, 2.6), Vec3(5.3, 8.2, 2.7), Vec3(-1, 8.2, 2.5)}};
    check_precrack(lattice_block(3, 8, 8, 6, 1.0, 2.015, {1, 0, 0}), quad, true);
    check_precrack(jittered_cloud(3, 8, 8, 6, 1.0, 2.015, {1, 0, 0}, 0.3, rng), quad, true);
    // A triangle, oblique to every lattice direction.
    const Precrack tri{{Vec3(1.2, 0.7, 0.3), Vec3(6.1, 2.2, 4.4), Vec3(2.0, 6.5, 3.1)}};
    check_precrack(jittered_cloud(3, 8, 8, 6, 1.0, 2.015, {1, 0, 0}, 0.3, rng), tri, true);
  }
}

TEST_CASE("a pre-crack removes the force across it", "[damage]") {
  // Two halves of a 2D strip, cut apart along y = 2.5 over the whole width: pulling the top
  // half up must leave the bottom half force free. Also without a critical stretch (an
  // elastic body with a crack).
  for (const double sc : {0.5, std::numeric_limits<double>::infinity()}) {
    INFO("critical stretch " << sc);
    ckpd::BodyDefinition d = lattice_block(2, 8, 6, 1, 1.0, 2.015, {1, 0, 0});
    d.critical_stretch = sc;
    d.precracks = {Precrack{{Vec3(-1, 2.5, 0), Vec3(8, 2.5, 0)}}};
    Body body = ckpd::make_body(d);
    for (std::size_t i = 0; i < body.size(); ++i)
      body.displacement[i] = body.reference_position[i].y() > 2.5 ? Vec3(0, 0.1, 0) : Vec3::Zero();
    ckpd::compute_internal_force(body, false);
    double largest = 0;
    for (const Vec3& f : body.force_density) largest = std::max(largest, f.norm());
    CHECK(largest == 0);
    CHECK(ckpd::max_point_damage(body) > 0);
  }
}

TEST_CASE("a pre-crack with the wrong number of corners throws", "[damage]") {
  Body flat = ckpd::make_body(lattice_block(2, 4, 4, 1, 1.0, 1.5, {1, 0, 0}));
  Body solid = ckpd::make_body(lattice_block(3, 3, 3, 3, 1.0, 1.5, {1, 0, 0}));
  CHECK_THROWS_AS(ckpd::apply_precrack(flat, Precrack{{Vec3(0, 0, 0)}}), std::invalid_argument);
  CHECK_THROWS_AS(
      ckpd::apply_precrack(flat, Precrack{{Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(2, 0, 0)}}),
      std::invalid_argument);
  CHECK_THROWS_AS(ckpd::apply_precrack(flat, Precrack{{Vec3(1, 1, 0), Vec3(1, 1, 0)}}),
                  std::invalid_argument);  // zero length
  CHECK_THROWS_AS(ckpd::apply_precrack(solid, Precrack{{Vec3(0, 0, 0), Vec3(1, 1, 0)}}),
                  std::invalid_argument);
  CHECK_THROWS_AS(ckpd::apply_precrack(solid, Precrack{}), std::invalid_argument);
  CHECK_THROWS_AS(  // collinear: zero area
      ckpd::apply_precrack(solid, Precrack{{Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2)}}),
      std::invalid_argument);
  CHECK_THROWS_AS(  // not planar
      ckpd::apply_precrack(
          solid, Precrack{{Vec3(0, 0, 1.1), Vec3(2, 0, 1.1), Vec3(2, 2, 1.1), Vec3(0, 2, 1.6)}}),
      std::invalid_argument);
  // Through make_body as well.
  ckpd::BodyDefinition d = lattice_block(2, 4, 4, 1, 1.0, 1.5, {1, 0, 0});
  d.precracks = {Precrack{{Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(2, 0, 0)}}};
  CHECK_THROWS_AS(ckpd::make_body(d), std::invalid_argument);
  // The valid ones do not throw.
  CHECK_NOTHROW(ckpd::apply_precrack(flat, Precrack{{Vec3(0.5, -1, 0), Vec3(0.5, 5, 0)}}));
  CHECK_NOTHROW(ckpd::apply_precrack(
      solid, Precrack{{Vec3(-1, -1, 1.5), Vec3(3, -1, 1.5), Vec3(3, 3, 1.5)}}));
}

TEST_CASE("a fast rigid spin breaks no bond: the stretch is objective", "[damage]") {
  // A 3D block spinning at 2e5 rad/s about a generic axis through a point outside it (tip
  // speeds of several hundred m/s); the rotation is applied exactly as u = (R - I) X.
  const double dx = 1e-3, sc = 1e-4, omega = 2e5;
  ckpd::BodyDefinition d = lattice_block(3, 6, 6, 6, dx, 2.015, {1, 0, 0});
  for (Vec3& p : d.reference_position) p += Vec3(2e-3, -1e-3, 1.5e-3);
  d.critical_stretch = sc;
  Body body = ckpd::make_body(d);
  const Vec3 axis = Vec3(0.3, 0.9, -0.4).normalized();
  double largest_nonobjective = 0, tip_speed = 0;
  for (const double t : {1e-6, 5e-6, 1.2e-5, 1.5708e-5, 2.5e-5}) {
    const double angle = omega * t;
    INFO("angle " << angle << " rad");
    const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
    for (std::size_t i = 0; i < body.size(); ++i) {
      const Vec3& X = body.reference_position[i];
      body.displacement[i] = (R - Eigen::Matrix3d::Identity()) * X;
      body.velocity[i] = omega * axis.cross(R * X);
      tip_speed = std::max(tip_speed, body.velocity[i].norm());
    }
    CHECK(ckpd::update_bond_failure(body) == 0);
    // The non-objective measure |du| / |dX| of seed 000 eq. 3.2 would break bonds here.
    for (std::size_t i = 0; i < body.size(); ++i)
      for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k) {
        const std::size_t j = body.family.neighbour[k];
        const Vec3 dX = body.reference_position[j] - body.reference_position[i];
        largest_nonobjective = std::max(
            largest_nonobjective, (body.displacement[j] - body.displacement[i]).norm() / dX.norm());
      }
  }
  CHECK(ckpd::failed_bond_count(body) == 0);
  CHECK(ckpd::max_point_damage(body) == 0);
  CHECK(tip_speed > 500);
  CHECK(largest_nonobjective > 1000 * sc);

  // A real stretch of 2.5 s_c along x on top of the spin breaks exactly the bonds whose
  // objective stretch |(I + E) dX| / |dX| - 1 exceeds s_c.
  Eigen::Matrix3d E = Eigen::Matrix3d::Zero();
  E(0, 0) = 2.5 * sc;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(2.0, axis).toRotationMatrix();
  for (std::size_t i = 0; i < body.size(); ++i)
    body.displacement[i] = (R * (Eigen::Matrix3d::Identity() + E) - Eigen::Matrix3d::Identity()) *
                           body.reference_position[i];
  const std::size_t failed = ckpd::update_bond_failure(body);
  CHECK(failed > 0);
  CHECK(failed < body.bond_count());
  for (std::size_t i = 0; i < body.size(); ++i)
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k) {
      const std::size_t j = body.family.neighbour[k];
      const Vec3 dX = body.reference_position[j] - body.reference_position[i];
      const double s = ((Eigen::Matrix3d::Identity() + E) * dX).norm() / dX.norm() - 1;
      CHECK((body.bond_intact[k] == 0) == (s > sc));
    }
}

TEST_CASE(
    "failing bonds book the strain energy they remove, at the step's midpoint when asked "
    "(bond-only fast path equals the per-point energies)",
    "[damage]") {
  std::mt19937 rng(23);
  for (const double half_drift : {0.0, 0.37}) {
    ckpd::BodyDefinition d = jittered_cloud(3, 6, 6, 5, 1.0, 2.2, {1, 0, 0}, 0.3, rng);
    d.critical_stretch = 0.02;
    Body body = ckpd::make_body(d);
    REQUIRE(!body.has_pairs());
    perturb(body, 0.05, rng);
    std::uniform_real_distribution<double> u(-0.05, 0.05);
    for (auto& v : body.velocity) v = Vec3(u(rng), u(rng), u(rng));
    // The oracle: the body's strain energy (per-point reference evaluation) before and after
    // the failures, both read at the booking displacement u - half_drift v.
    Body at_booking = body;
    for (std::size_t i = 0; i < body.size(); ++i)
      at_booking.displacement[i] -= half_drift * body.velocity[i];
    auto energy = [](const Body& b) {
      ckpd::FamilyScratch scratch;
      double e = 0;
      for (std::size_t i = 0; i < b.size(); ++i)
        e += b.volume[i] * ckpd::evaluate_point(b, i, scratch).strain_energy_density();
      return e;
    };
    const double before = energy(at_booking);
    const auto update = ckpd::fail_overstretched_bonds(body, half_drift);
    REQUIRE(update.failed > 0);
    at_booking.bond_intact = body.bond_intact;
    const double after = energy(at_booking);
    INFO("half_drift " << half_drift << ": booked " << update.dissipated << ", oracle "
                       << before - after);
    CHECK(update.dissipated == Approx(before - after).epsilon(1e-12));
    // The decision is made at the end-of-step displacement.
    CHECK(ckpd::failed_bond_count(body) == update.failed);
  }
}
