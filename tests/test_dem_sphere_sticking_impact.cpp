// A DEM sphere striking a fixed wall nearly head-on (v_t / v_n = 0.1 and 0.5, below the sliding
// limit 3.5 mu (1 + e) = 2): the contact sticks, the tangential spring stores the motion and
// turns it over (Maw, Barber and Fawcett 1976), so the rebound's v_t' and omega R are set by the
// spring's oscillation against the sphere's mass and inertia together. Compared with a finely
// integrated reference of the same law written here on its own: a sphere of mass m and inertia
// 2/5 m R^2 in the x-z plane, Hertz normal force with the dashpot of e, Mindlin's tangential
// spring k_t = 8 G* sqrt(R delta) with Coulomb's cap, acting at the wall (arm: the centre's
// height), by symplectic Euler at a step ten thousand times below the program's.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "dem_sphere_fixtures.hpp"
#include "src/case/case_loader.hpp"

using namespace ckpd;
using namespace ckpd::testing;

namespace {

struct Rebound {
  double vx = 0, vz = 0, spin = 0;  // spin about +y
};

// The reference: the sphere starts touching (height R) with (vx, -vn), no spin.
Rebound reference(double radius, double density, double modulus, double poisson, double e,
                  double mu, double vx, double vn, double dt) {
  const double mass = density * 4.0 / 3 * std::numbers::pi * std::pow(radius, 3);
  const double inertia = 0.4 * mass * radius * radius;
  // Two equal bodies: E* = E / (2 (1 - nu^2)), G* = G / (2 (2 - nu)) with G = E / (2 (1 + nu)).
  const double e_star = modulus / (2 * (1 - poisson * poisson));
  const double g_star = modulus / (2 * (1 + poisson)) / (2 * (2 - poisson));
  const double l = std::log(e);
  const double zeta =
      std::sqrt(5.0 / 6) * -l / std::sqrt(l * l + std::numbers::pi * std::numbers::pi);
  double z = radius, vz = -vn, w = 0, xi = 0;
  for (long long step = 0; step < 100'000'000; ++step) {
    const double delta = radius - z;
    if (delta <= 0 && step > 0) break;
    double fz = 0, fx = 0;
    if (delta > 0) {
      const double root = std::sqrt(radius * delta);
      const double kn = 2 * e_star * root, kt = 8 * g_star * root;
      fz = 4.0 / 3 * e_star * root * delta - 2 * zeta * std::sqrt(kn * mass) * vz;
      // The wall's material is still; the sphere's at the contact moves with vx - h omega_y.
      xi += dt * (vx - z * w);
      const double limit = mu * std::max(fz, 0.0);
      if (kt * std::abs(xi) > limit) xi = std::copysign(limit / kt, xi);
      fx = -kt * xi;
    }
    vz += dt * fz / mass;
    vx += dt * fx / mass;
    w += dt * -z * fx / inertia;  // (0, 0, -h) x (fx, 0, 0) = (0, -h fx, 0)
    z += dt * vz;
  }
  return {vx, vz, w};
}

}  // namespace

TEST_CASE(
    "a DEM sphere in the sticking regime turns its tangential velocity over as the "
    "integrated law does",
    "[dem][dem_sphere]") {
  const double radius = 0.005, e = 0.9, mu = 0.3, vn = 1.0;
  // v_t / v_n = 0.1: the contact sticks throughout and the spring's oscillation sends the sphere
  // off with nearly its tangential velocity and little spin (v_t' / v_t = +0.99; the sphere
  // without inertia bounced back at -1.06). 0.5: it slips, then leaves rolling.
  for (const double vt : {0.1, 0.5}) {
    const auto dir = fresh_dir("dem-sticking");
    std::string text = "bodies:\n";
    // Starting just above the wall: the approach takes a few steps.
    text += dem_sphere_entry("ball", Vec3(0, 0, radius + 2e-6), radius, Vec3(vt, 0, -vn));
    text += glass_floor_entry(dir);
    text += hertz_mindlin_contact(e, mu);
    text += "time: {end: 1e-4}\n";
    Scene scene = load_scene(write_file(dir / "case.yaml", text));
    Simulation sim(scene);
    REQUIRE(run_through_contact(sim));
    const RigidMotion& ball = *scene.bodies[0].rigid;
    const Rebound got{ball.velocity().x(), ball.velocity().z(), ball.angular_velocity().y()};
    const double program_dt = sim.step_choice().dt;
    // The reference at two steps: it has converged to far below the tolerance.
    const double fine = 1e-10;
    REQUIRE(fine < program_dt / 1000);
    const Rebound ref =
        reference(radius, kGlassDensity, kGlassModulus, kGlassPoisson, e, mu, vt, vn, fine);
    const Rebound half =
        reference(radius, kGlassDensity, kGlassModulus, kGlassPoisson, e, mu, vt, vn, fine / 2);
    INFO("v_t " << vt << ": program (dt " << program_dt << " s): v_t' " << got.vx << ", omega R "
                << got.spin * radius << ", v_n' " << got.vz << "; reference: v_t' " << ref.vx
                << ", omega R " << ref.spin * radius << ", v_n' " << ref.vz
                << " (at half its step: " << half.vx << ", " << half.spin * radius << ")");
    CHECK(std::abs(half.vx - ref.vx) < 1e-4 * vt);
    CHECK(std::abs(half.spin - ref.spin) * radius < 1e-4 * vt);
    CHECK(std::abs(got.vx - ref.vx) < 0.01 * vt);
    CHECK(std::abs(got.spin - ref.spin) * radius < 0.01 * vt);
    CHECK(got.vz == Approx(ref.vz).epsilon(0.01));
    // At 0.1 neither Coulomb's rigid body (sticking: it leaves rolling, v_t' = 5/7 v_t, as it
    // does at 0.5) nor a sphere that cannot spin: the spring and the inertia set the rebound.
    if (vt < 0.2) CHECK(std::abs(ref.vx - 5.0 / 7 * vt) > 0.2 * vt);
    if (vt < 0.2) CHECK(got.vx > 0.9 * vt);
  }
}
