// The corotated far field (bodies/far_field.hpp, `far_field: {tolerance: T, corotated: true}`):
// the polar rotation is recovered from F = R U; a rigid motion of any size leaves every point
// linear with zero force and energy; under a large rotation with a small strain on top the
// corotated linear force's error against the exact force falls like the strain (the plain
// linearisation's does not fall at all); without rotation the corotated rows are the plain ones.
// 2D and 3D, lattice and jittered cloud, both force forms, 1 and 2 threads.
#include <omp.h>

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "bodies/body.hpp"
#include "bodies/far_field.hpp"
#include "bodies/linear_operator.hpp"
#include "kernel_comparison.hpp"
#include "reference/internal_force.hpp"

using ckpd::Body;
using ckpd::ForceForm;
using ckpd::Vec3;

namespace {

struct RotatedScene {
  kernel_comparison::Scene scene;
  ForceForm form;
};

const std::vector<RotatedScene>& scenes() {
  static const std::vector<RotatedScene> all = [] {
    std::vector<RotatedScene> v;
    const std::vector<kernel_comparison::Scene> geometry = {
        {"2D lattice, nu=0.4", 2, 0.4, 0.0, 10, 9, 1},
        {"2D jittered cloud, nu=0.3", 2, 0.3, 0.2, 10, 9, 1},
        {"3D lattice, nu=0.3", 3, 0.3, 0.0, 6, 5, 5},
        {"3D jittered cloud", 3, 0.3, 0.2, 6, 5, 5},
    };
    for (const auto& g : geometry)
      for (ForceForm f : {ForceForm::own_family, ForceForm::energy_consistent}) v.push_back({g, f});
    return v;
  }();
  return all;
}

std::string label(const RotatedScene& rs) {
  return rs.scene.label + ", " + ckpd::to_string(rs.form);
}

Body scene_body(const RotatedScene& rs) {
  using namespace kernel_comparison;
  const Scene& s = rs.scene;
  std::mt19937 rng(5);
  ckpd::BodyDefinition d =
      block(s.dimension, s.nx, s.ny, s.nz, constants_for(s), s.jitter, rng, s.m);
  d.force_form = rs.form;
  return ckpd::make_body(std::move(d));
}

// A rotation by `angle` about a fixed oblique axis (about z in 2D).
Eigen::Matrix3d rotation(int dimension, double angle) {
  const Vec3 axis = dimension == 2 ? Vec3(0, 0, 1) : Vec3(1, -2, 3).normalized();
  return Eigen::AngleAxisd(angle, axis).toRotationMatrix();
}

// A symmetric strain of unit size (in the plane in 2D).
Eigen::Matrix3d strain(int dimension) {
  Eigen::Matrix3d E;
  E << 0.8, 0.3, -0.2, 0.3, -0.5, 0.4, -0.2, 0.4, 0.6;
  if (dimension == 2) E.row(2).setZero(), E.col(2).setZero();
  return E;
}

// u = Q (I + e E) X + c - X about the body's first point: a rotated uniform strain, moved by c
// (a fraction of the spacing) unless `translated` is false.
void deform(Body& body, const Eigen::Matrix3d& Q, double e, const Eigen::Matrix3d& E,
            bool translated = true) {
  const double t = translated ? kernel_comparison::kDx : 0.0;
  const Vec3 c(0.3 * t, -0.2 * t, body.dimension == 3 ? 0.1 * t : 0.0);
  const Vec3 X0 = body.reference_position[0];
  for (std::size_t i = 0; i < body.size(); ++i) {
    const Vec3 X = body.reference_position[i] - X0;
    // Q X - X and Q (e E X) added separately: the strain part is not lost to rounding.
    body.displacement[i] = (Q * X - X) + Q * (e * (E * X)) + c;
  }
}

std::vector<Vec3> exact_force(Body& body) {
  ckpd::compute_internal_force(body, false);
  return body.force_density;
}

// Every point linear: the far field's force is the linear rows' throughout.
std::vector<Vec3> far_field_force(Body& body, ckpd::FarField& ff, bool energy = false) {
  ckpd::compute_internal_force_far_field(body, ff, energy);
  return body.force_density;
}

double max_difference(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, (a[i] - b[i]).norm());
  return d;
}

}  // namespace

TEST_CASE("the polar rotation of F = R U is R, and an inverted F has none", "[far_field]") {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 50; ++trial) {
    const Vec3 axis = Vec3(u(rng), u(rng), u(rng)).normalized();
    const Eigen::Matrix3d R = Eigen::AngleAxisd(3.0 * u(rng), axis).toRotationMatrix();
    Eigen::Matrix3d S = Eigen::Matrix3d::Random();
    S = 0.5 * (S + S.transpose()).eval();
    const double size = trial < 25 ? 1e-3 : 0.3;  // a linear point's strain, and a large one
    const Eigen::Matrix3d U = Eigen::Matrix3d::Identity() + size * S;
    Eigen::Matrix3d found;
    REQUIRE(ckpd::polar_rotation(R * U, found));
    INFO("trial " << trial << ", stretch " << size);
    CHECK((found - R).norm() < 1e-14);
  }
  Eigen::Matrix3d mirrored = Eigen::Matrix3d::Identity();
  mirrored(0, 0) = -1;
  Eigen::Matrix3d untouched = Eigen::Matrix3d::Zero();
  CHECK_FALSE(ckpd::polar_rotation(mirrored, untouched));
  CHECK(untouched.isZero());
}

TEST_CASE(
    "corotated far field: a rigid motion of any size keeps every point linear with zero force "
    "and energy, where the plain screen sends every point exact",
    "[far_field]") {
  kernel_comparison::ThreadCountGuard guard;
  for (const RotatedScene& rs : scenes()) {
    Body body = scene_body(rs);
    // The force of a strain of 1e-3: the scale the rigid motion's force must vanish against.
    deform(body, Eigen::Matrix3d::Identity(), 1e-3, strain(body.dimension));
    const double scale = kernel_comparison::max_norm(exact_force(body));
    REQUIRE(scale > 0);
    for (const double angle : {1e-3, 2.5}) {
      deform(body, rotation(body.dimension, angle), 0.0, strain(body.dimension));
      for (int threads = 1; threads <= (angle > 1 ? 2 : 1); ++threads) {
        omp_set_num_threads(threads);
        INFO(label(rs) << ", angle " << angle << " rad, " << threads << " threads");
        ckpd::FarField corotated = ckpd::make_far_field(body, 1e-6, true);
        const std::vector<Vec3> b = far_field_force(body, corotated, true);
        CHECK(corotated.exact_count == 0);
        CHECK(kernel_comparison::max_norm(b) < 1e-9 * scale);
        CHECK(kernel_comparison::max_abs(body.strain_energy_density) <
              1e-18 * scale * kernel_comparison::kDx);
        ckpd::FarField plain = ckpd::make_far_field(body, 1e-6, false);
        far_field_force(body, plain);
        CHECK(plain.exact_count == body.size());
      }
    }
  }
}

TEST_CASE(
    "corotated far field: under a large rotation the linear force's error against the exact "
    "force falls like the strain",
    "[far_field]") {
  for (const RotatedScene& rs : scenes()) {
    Body body = scene_body(rs);
    const Eigen::Matrix3d Q = rotation(body.dimension, 0.7);
    auto relative_error = [&](double e, bool corotated) {
      deform(body, Q, e, strain(body.dimension));
      const std::vector<Vec3> exact = exact_force(body);
      ckpd::FarField ff = ckpd::make_far_field(body, 1.0, corotated);  // T = 1: all linear
      const std::vector<Vec3> linear = far_field_force(body, ff);
      REQUIRE(ff.exact_count == 0);
      return max_difference(linear, exact) / kernel_comparison::max_norm(exact);
    };
    const double e3 = relative_error(1e-3, true), e5 = relative_error(1e-5, true);
    const double slope = std::log10(e3 / e5) / 2;
    const double plain = relative_error(1e-4, false);
    INFO(label(rs) << ": corotated error " << e3 << " at strain 1e-3, " << e5 << " at 1e-5 (slope "
                   << slope << "); plain linearisation " << plain << " at 1e-4");
    CHECK(slope == Approx(1.0).margin(0.15));
    CHECK(e3 < 1e-2);
    CHECK(plain > 10);  // the rotation's own force, 0.7 rad against a strain of 1e-4
  }
}

TEST_CASE(
    "corotated far field without rotation: the rows equal the plain linear rows, the energy the "
    "quadratic energy",
    "[far_field]") {
  for (const RotatedScene& rs : scenes()) {
    Body body = scene_body(rs);
    // A symmetric strain: its polar rotation is the identity. Not translated: the plain rows
    // act on u^i itself, and their blocks sum to zero only to the assembly's rounding (about
    // 1e-11 of a block), which a translation of 0.3 dx against relative displacements of 1e-4
    // dx turns into 1e-8 of the force; the corotated rows see relative displacements only.
    deform(body, Eigen::Matrix3d::Identity(), 1e-4, strain(body.dimension), false);
    ckpd::FarField plain = ckpd::make_far_field(body, 1.0, false);
    const std::vector<Vec3> b_plain = far_field_force(body, plain, true);
    const std::vector<double> w_plain = body.strain_energy_density;
    ckpd::FarField corotated = ckpd::make_far_field(body, 1.0, true);
    const std::vector<Vec3> b_corotated = far_field_force(body, corotated, true);
    INFO(label(rs));
    REQUIRE(corotated.exact_count == 0);
    double rotation_error = 0;
    for (const Eigen::Matrix3d& R : corotated.rotation)
      rotation_error = std::max(rotation_error, (R - Eigen::Matrix3d::Identity()).norm());
    CHECK(rotation_error < 1e-12);
    CHECK(max_difference(b_corotated, b_plain) < 1e-9 * kernel_comparison::max_norm(b_plain));
    double w_difference = 0;
    for (std::size_t i = 0; i < body.size(); ++i)
      w_difference = std::max(w_difference, std::abs(body.strain_energy_density[i] - w_plain[i]));
    CHECK(w_difference < 1e-9 * kernel_comparison::max_abs(w_plain));
  }
}
