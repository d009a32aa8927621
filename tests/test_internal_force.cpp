// CKPD internal force (THEORY.md section 2): the symmetric unordered kernel against the ordered
// reference, forces as energy gradients, rigid-motion invariance, and skipped zero families.
#include <Eigen/Geometry>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "bodies/material.hpp"
#include "body_fixtures.hpp"
#include "reference/internal_force.hpp"
#include "reference_kernel.hpp"

namespace {

using ckpd::Body;
using ckpd::InteractionConstants;
using ckpd::PlaneMode;
using ckpd::Vec3;
using namespace ckpd_test;

constexpr double kE = 210e9;
constexpr double kDx = 1e-3;

InteractionConstants constants_for(int dimension, double nu, PlaneMode plane, double m) {
  return ckpd::interaction_constants(dimension, kE, nu, plane, m * kDx);
}

struct Scene {
  std::string label;
  ckpd::BodyDefinition definition;
  bool lattice = true;
};

// The bodies the kernel comparisons run on: 2D lattices with C2 < 0 and C2 > 0, 3D lattices
// with C3 > 0 and C3 < 0, and jittered (irregular) clouds in both dimensions.
std::vector<Scene> comparison_scenes() {
  std::mt19937 rng(20240611);
  std::vector<Scene> s;
  s.push_back(
      {"2D lattice, plane stress nu=0.2 (C2<0)",
       lattice_block(2, 8, 7, 1, kDx, 3.015, constants_for(2, 0.2, PlaneMode::stress, 3.015))});
  s.push_back(
      {"2D lattice, plane stress nu=0.4 (C2>0)",
       lattice_block(2, 8, 7, 1, kDx, 3.015, constants_for(2, 0.4, PlaneMode::stress, 3.015))});
  s.push_back(
      {"3D lattice, nu=0.3 (C3>0)",
       lattice_block(3, 5, 5, 4, kDx, 2.015, constants_for(3, 0.3, PlaneMode::none, 2.015))});
  s.push_back(
      {"3D lattice, nu=0.1 (C3<0)",
       lattice_block(3, 5, 4, 4, kDx, 2.515, constants_for(3, 0.1, PlaneMode::none, 2.515))});
  s.push_back({"2D jittered cloud, plane strain nu=0.35",
               jittered_cloud(2, 7, 7, 1, kDx, 2.8, constants_for(2, 0.35, PlaneMode::strain, 2.8),
                              0.25, rng),
               false});
  s.push_back({"3D jittered cloud, nu=0.15",
               jittered_cloud(3, 5, 4, 4, kDx, 2.2, constants_for(3, 0.15, PlaneMode::none, 2.2),
                              0.25, rng),
               false});
  return s;
}

double max_norm(const std::vector<Vec3>& v) {
  double m = 0;
  for (const Vec3& x : v) m = std::max(m, x.norm());
  return m;
}

// Compares compute_internal_force and evaluate_point with the ordered reference on every point.
void check_against_reference(Body& body, bool lattice) {
  ckpd::compute_internal_force(body, true);
  ckpd::FamilyScratch scratch;
  std::vector<ReferenceResult> reference(body.size());
  std::vector<Vec3> reference_force(body.size());
  for (std::size_t i = 0; i < body.size(); ++i) {
    reference[i] = reference_point(body, i);
    reference_force[i] = reference[i].force();
    // The body's counts of ordered non-degenerate sets are the reference's.
    CHECK(reference[i].n1 == body.family.family_size(i));
    CHECK(reference[i].n2 == body.n2[i]);
    CHECK(reference[i].n3 == body.n3[i]);
  }
  const double scale = max_norm(reference_force);
  REQUIRE(scale > 0);
  double allowance = 0;
  for (const ReferenceResult& r : reference) allowance = std::max(allowance, r.force_allowance);
  INFO("largest rounding allowance of nearly flat sets, relative: " << allowance / scale);
  if (lattice) CHECK(allowance == 0);
  // Energies per family, each against its own largest value (W1 and W3 have opposite signs
  // when C3 < 0, so their sum is no scale).
  // Errors are measured beyond the rounding allowance of nearly flat sets (reference_kernel.hpp),
  // which is zero on lattices.
  double w_scale[3] = {0, 0, 0}, w_error[3] = {0, 0, 0}, force_error = 0, density_error = 0;
  for (std::size_t i = 0; i < body.size(); ++i) {
    const ReferenceResult& r = reference[i];
    const ckpd::PointResult p = ckpd::evaluate_point(body, i, scratch);
    const double fa = r.force_allowance, ea = r.energy_allowance;
    force_error = std::max(force_error, (p.force_density - r.force()).norm() - fa);
    force_error = std::max(force_error, (body.force_density[i] - r.force()).norm() - fa);
    const double got[3] = {p.w1, p.w2, p.w3}, want[3] = {r.w1, r.w2, r.w3};
    for (int n = 0; n < 3; ++n) {
      w_scale[n] = std::max(w_scale[n], std::abs(want[n]));
      w_error[n] = std::max(w_error[n], std::abs(got[n] - want[n]) - ea);
    }
    density_error =
        std::max(density_error,
                 std::abs(body.strain_energy_density[i] - (r.w1 / 2 + r.w2 / 3 + r.w3 / 4)) - ea);
  }
  INFO("max force " << scale << ", max force error " << force_error);
  CHECK(force_error <= 1e-12 * scale);
  for (int n = 0; n < 3; ++n) {
    INFO("W" << n + 1 << ": largest " << w_scale[n] << ", largest error " << w_error[n]);
    CHECK(w_error[n] <= 1e-12 * w_scale[n]);
  }
  CHECK(density_error <= 1e-12 * (w_scale[0] + w_scale[1] + w_scale[2]));
  CHECK(w_scale[0] > 0);
  CHECK(w_scale[1] + w_scale[2] > 0);
}

}  // namespace

TEST_CASE("symmetric unordered summation equals the ordered reference sums", "[internal_force]") {
  std::mt19937 rng(7);
  for (const Scene& scene : comparison_scenes()) {
    for (const bool with_failures : {false, true}) {
      ckpd::BodyDefinition d = scene.definition;
      d.critical_stretch = 0.5;  // damage bookkeeping on; no bond reaches it here
      Body body = ckpd::make_body(d);
      perturb(body, 0.02 * kDx, rng);
      std::size_t failed = 0;
      if (with_failures) {
        failed = fail_random_bonds(body, 0.15, rng);
        REQUIRE(failed > 0);
      }
      INFO(scene.label << (with_failures ? ", with failed bonds" : ", all bonds intact"));
      check_against_reference(body, scene.lattice);
    }
  }
}

TEST_CASE("the ordered reference three-neighbour force does not vanish (the sign trap)",
          "[internal_force]") {
  // Guards the reference itself: summing the six orders of a triple with one sign (the
  // published Julia mistake) gives zero b3, which the reference must not reproduce.
  ckpd::BodyDefinition d = lattice_block(3, 4, 4, 4, kDx, 2.015,
                                         {0, 0, constants_for(3, 0.1, PlaneMode::none, 2.015).c3});
  Body body = ckpd::make_body(d);
  std::mt19937 rng(3);
  perturb(body, 0.02 * kDx, rng);
  double largest = 0;
  for (std::size_t i = 0; i < body.size(); ++i)
    largest = std::max(largest, reference_point(body, i).b3.norm());
  CHECK(largest > 0);
}

namespace {

// Central finite differences of the own-family energy W^i = w1 + w2 + w3 with respect to x^i.
void check_force_is_energy_gradient(Body& body, double step) {
  ckpd::FamilyScratch scratch;
  double scale = 0;
  std::vector<Vec3> force(body.size());
  for (std::size_t i = 0; i < body.size(); ++i) {
    force[i] = ckpd::evaluate_point(body, i, scratch).force_density;
    scale = std::max(scale, force[i].norm());
  }
  REQUIRE(scale > 0);
  auto energy = [&](std::size_t i) {
    const ckpd::PointResult r = ckpd::evaluate_point(body, i, scratch);
    return r.w1 + r.w2 + r.w3;
  };
  double worst = 0;
  for (std::size_t i = 0; i < body.size(); ++i) {
    Vec3 gradient = Vec3::Zero();
    for (int c = 0; c < body.dimension; ++c) {
      const double saved = body.displacement[i][c];
      body.displacement[i][c] = saved + step;
      const double plus = energy(i);
      body.displacement[i][c] = saved - step;
      const double minus = energy(i);
      body.displacement[i][c] = saved;
      gradient[c] = (plus - minus) / (2 * step);
    }
    worst = std::max(worst, (force[i] + gradient).norm() / scale);
  }
  INFO("largest |b + dW/dx| relative to the largest force: " << worst);
  CHECK(worst < 1e-6);
}

}  // namespace

TEST_CASE("each interaction family's force is minus the gradient of its own-family energy",
          "[internal_force]") {
  std::mt19937 rng(11);
  const double m2 = 3.015, m3 = 2.215;
  const InteractionConstants c2d = constants_for(2, 0.2, PlaneMode::stress, m2);
  const InteractionConstants c3d = constants_for(3, 0.1, PlaneMode::none, m3);
  struct Family {
    std::string label;
    int dimension;
    InteractionConstants constants;
  };
  const std::vector<Family> families = {
      {"2D one-neighbour only", 2, {c2d.c1, 0, 0}},
      {"2D two-neighbour only", 2, {0, c2d.c2, 0}},
      {"2D two-neighbour only, C2 > 0", 2, {0, -c2d.c2, 0}},
      {"3D one-neighbour only", 3, {c3d.c1, 0, 0}},
      {"3D three-neighbour only", 3, {0, 0, c3d.c3}},
      {"3D three-neighbour only, C3 > 0", 3, {0, 0, -c3d.c3}},
  };
  for (const Family& f : families) {
    for (const bool irregular : {false, true}) {
      INFO(f.label << (irregular ? ", jittered cloud" : ", lattice"));
      const double m = f.dimension == 3 ? m3 : m2;
      const int nz = f.dimension == 3 ? 4 : 1;
      ckpd::BodyDefinition d =
          irregular ? jittered_cloud(f.dimension, 5, 5, nz, kDx, m, f.constants, 0.25, rng)
                    : lattice_block(f.dimension, 5, 5, nz, kDx, m, f.constants);
      Body body = ckpd::make_body(d);
      perturb(body, 0.03 * kDx, rng);
      check_force_is_energy_gradient(body, 1e-6 * kDx);
    }
  }
}

namespace {

// The largest force under a small homogeneous strain of size eps (mixed normal and shear).
double strain_force_scale(Body body, double eps) {
  Eigen::Matrix3d e;
  e << 1.0, 0.4, -0.3, 0.4, -0.7, 0.2, -0.3, 0.2, 0.5;
  if (body.dimension == 2) e.row(2).setZero(), e.col(2).setZero();
  for (std::size_t i = 0; i < body.size(); ++i)
    body.displacement[i] = eps * e * body.reference_position[i];
  ckpd::compute_internal_force(body, false);
  return max_norm(body.force_density);
}

void check_rigid_motion_is_force_free(Body body, const Eigen::Matrix3d& rotation,
                                      const Vec3& translation, double tolerance) {
  for (std::size_t i = 0; i < body.size(); ++i) {
    const Vec3& X = body.reference_position[i];
    body.displacement[i] = (rotation - Eigen::Matrix3d::Identity()) * X + translation;
  }
  ckpd::compute_internal_force(body, true);
  const double largest = max_norm(body.force_density);
  INFO("largest force " << largest << ", tolerance " << tolerance);
  CHECK(largest <= tolerance);
  double energy = 0;
  for (double w : body.strain_energy_density) energy = std::max(energy, w);
  CHECK(energy <= 1e-20 * kE);
}

}  // namespace

TEST_CASE("rigid translation and rigid rotation produce no force", "[internal_force]") {
  std::mt19937 rng(5);
  const double deg = std::numbers::pi / 180;
  const std::vector<double> angles = {1e-4, 1 * deg, 30 * deg, 90 * deg, 180 * deg};
  struct Case {
    std::string label;
    ckpd::BodyDefinition definition;
    Vec3 axis;
  };
  const std::vector<Case> cases = {
      {"3D lattice, nu=0.3",
       lattice_block(3, 5, 5, 5, kDx, 2.015, constants_for(3, 0.3, PlaneMode::none, 2.015)),
       Vec3(0.3, -0.5, 0.8).normalized()},
      {"3D jittered cloud, nu=0.1",
       jittered_cloud(3, 5, 5, 4, kDx, 2.2, constants_for(3, 0.1, PlaneMode::none, 2.2), 0.25, rng),
       Vec3(-0.7, 0.2, 0.4).normalized()},
      {"2D lattice, plane stress nu=0.2",
       lattice_block(2, 8, 8, 1, kDx, 3.015, constants_for(2, 0.2, PlaneMode::stress, 3.015)),
       Vec3::UnitZ()},
      {"2D jittered cloud, plane stress nu=0.45",
       jittered_cloud(2, 8, 7, 1, kDx, 3.015, constants_for(2, 0.45, PlaneMode::stress, 3.015),
                      0.25, rng),
       Vec3::UnitZ()},
  };
  for (const Case& c : cases) {
    INFO(c.label);
    ckpd::BodyDefinition d = c.definition;
    // Move the body away from the origin so rotations also move it a lot.
    for (Vec3& p : d.reference_position) p += Vec3(0.0123, -0.0071, c.axis.z() == 1 ? 0 : 0.0049);
    const Body body = ckpd::make_body(d);
    // A strain of 1e-6 gives this force; rigid motion must give 1e5 times less (the force of a
    // strain of 1e-11, a few hundred roundings of the displacements used here).
    const double scale = strain_force_scale(body, 1e-6);
    REQUIRE(scale > 0);
    const double tolerance = 1e-5 * scale;
    // Translation is exact in any size; combined with rotation it is kept to a few body sizes
    // so that the absolute displacements keep their precision.
    const Vec3 far = c.axis.z() == 1 ? Vec3(0.37, -1.21, 0) : Vec3(0.37, -1.21, 2.5);
    const Vec3 near = 0.01 * far;
    check_rigid_motion_is_force_free(body, Eigen::Matrix3d::Identity(), far, tolerance);
    for (const double angle : angles) {
      INFO("angle " << angle << " rad");
      const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, c.axis).toRotationMatrix();
      check_rigid_motion_is_force_free(body, R, Vec3::Zero(), tolerance);
      check_rigid_motion_is_force_free(body, R, near, tolerance);
    }
    // The same check fails for a strain of 1e-10: the test can fail.
    CHECK(strain_force_scale(body, 1e-10) > 5 * tolerance);
  }
}

TEST_CASE("a zero interaction constant means that family is not built", "[internal_force]") {
  SECTION("3D, nu = 0.25: C3 = 0 and no three-neighbour sets") {
    const double m = 2.015;
    const InteractionConstants c = constants_for(3, 0.25, PlaneMode::none, m);
    CHECK(c.c3 == 0);
    CHECK(c.c2 == 0);
    CHECK(c.c1 > 0);
    const Body body = ckpd::make_body(lattice_block(3, 4, 4, 4, kDx, m, c));
    CHECK_FALSE(body.has_triples());
    CHECK(body.total_three_neighbour() == 0);
    for (std::size_t i = 0; i < body.size(); ++i) CHECK(body.dv3[i] == 0);
    // With nu = 0.3 the same block does build them.
    const Body other = ckpd::make_body(
        lattice_block(3, 4, 4, 4, kDx, m, constants_for(3, 0.3, PlaneMode::none, m)));
    CHECK(other.has_triples());
    CHECK(other.total_three_neighbour() > 0);
  }
  SECTION("2D plane stress, nu = 1/3: C2 = 0 and no two-neighbour sets") {
    const double m = 3.015;
    const InteractionConstants c = constants_for(2, 1.0 / 3.0, PlaneMode::stress, m);
    CHECK(c.c2 == 0);
    CHECK(c.c3 == 0);
    CHECK(c.c1 > 0);
    const Body body = ckpd::make_body(lattice_block(2, 6, 6, 1, kDx, m, c));
    CHECK_FALSE(body.has_pairs());
    CHECK(body.total_two_neighbour() == 0);
    for (std::size_t i = 0; i < body.size(); ++i) CHECK(body.dv2[i] == 0);
    const Body other = ckpd::make_body(
        lattice_block(2, 6, 6, 1, kDx, m, constants_for(2, 0.3, PlaneMode::stress, m)));
    CHECK(other.has_pairs());
    CHECK(other.total_two_neighbour() > 0);
  }
}

namespace {

Body few_points(int dimension, std::vector<Vec3> positions, InteractionConstants constants) {
  ckpd::BodyDefinition d;
  d.name = "few";
  d.dimension = dimension;
  d.reference_position = std::move(positions);
  d.volume.assign(d.reference_position.size(), 1.0);
  d.density = 1;
  d.horizon = 2.5;
  d.constants = constants;
  d.full_family_volume = static_cast<double>(d.reference_position.size());
  return ckpd::make_body(d);
}

}  // namespace

TEST_CASE("nearly collinear and nearly coplanar sets follow the 1e-10 degeneracy rule",
          "[internal_force]") {
  SECTION("2D: a triangle (0,0), (1,0), (2,h) seen from each vertex") {
    // A / (L^ij L^ik) is h/2 at the outer vertices and h at the middle one.
    struct Case {
      double h;
      std::vector<std::uint32_t> n2;
    };
    for (const Case& c : std::vector<Case>{
             {3e-10, {2, 2, 2}}, {1.5e-10, {0, 2, 0}}, {0.5e-10, {0, 0, 0}}, {0.0, {0, 0, 0}}}) {
      INFO("h " << c.h);
      Body body = few_points(2, {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, c.h, 0)}, {1.0, -0.3, 0});
      CHECK(body.n2 == c.n2);
      body.displacement = {Vec3(0.01, -0.02, 0), Vec3(-0.01, 0.03, 0), Vec3(0.02, 0.01, 0)};
      ckpd::FamilyScratch scratch;
      for (std::size_t i = 0; i < 3; ++i) {
        const ReferenceResult r = reference_point(body, i);
        CHECK(r.n2 == body.n2[i]);
        const Vec3 f = ckpd::evaluate_point(body, i, scratch).force_density;
        CHECK((f - r.force()).norm() <= 1e-12 * r.force().norm());
      }
    }
  }
  SECTION("3D: a tetrahedron (0,0,0), (1,0,0), (0,1,0), (1,1,h)") {
    for (const double h : {1e-6, 1e-12}) {
      INFO("h " << h);
      Body body = few_points(3, {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, h)},
                             {1.0, 0, 0.7});
      for (std::size_t i = 0; i < 4; ++i) CHECK(body.n3[i] == (h > 1e-9 ? 6u : 0u));
      body.displacement = {Vec3(0.01, -0.02, 0.03), Vec3(-0.01, 0.03, 0.0), Vec3(0.02, 0.01, -0.01),
                           Vec3(0.0, 0.02, 0.01)};
      ckpd::FamilyScratch scratch;
      for (std::size_t i = 0; i < 4; ++i) {
        const ReferenceResult r = reference_point(body, i);
        CHECK(r.n3 == body.n3[i]);
        const Vec3 f = ckpd::evaluate_point(body, i, scratch).force_density;
        CHECK((f - r.force()).norm() <= 1e-12 * r.force().norm() + r.force_allowance);
      }
    }
  }
}
