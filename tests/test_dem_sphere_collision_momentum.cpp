// DEM spheres meeting each other and a free rigid body of points: the contact force acts at the
// point where the surfaces meet (R_a from a's centre, R_b from b's), equal and opposite on both,
// so linear momentum sum m v and angular momentum about a fixed point sum (c x m v + I omega)
// are conserved to rounding, while friction trades orbital for spin angular momentum. Two
// unequal spheres touch at R_a + R_b with Hertz's R* = R_a R_b / (R_a + R_b).
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "dem_sphere_fixtures.hpp"
#include "scene_momentum.hpp"
#include "src/case/case_loader.hpp"

using namespace ckpd;
using namespace ckpd::testing;

namespace {

struct Drift {
  double momentum = 0, angular = 0;  // largest relative changes over the run
  Vec3 spin_change = Vec3::Zero();   // of body 0
};

Drift run_and_watch(Scene& scene) {
  Simulation sim(scene);
  const SceneMomentum start = scene_momentum(scene);
  const Vec3 spin0 = scene.bodies[0].rigid->angular_velocity();
  Drift d;
  bool met = false;
  while (sim.step() < sim.planned_steps()) {
    sim.advance(false);
    const SceneMomentum now = scene_momentum(scene);
    d.momentum = std::max(d.momentum, (now.linear - start.linear).norm() / start.linear_scale);
    d.angular = std::max(d.angular, (now.angular - start.angular).norm() / start.angular_scale);
    const bool touching = sim.contact()->statistics().points_in_contact > 0;
    if (met && !touching) break;
    met = met || touching;
  }
  REQUIRE(met);
  d.spin_change = scene.bodies[0].rigid->angular_velocity() - spin0;
  return d;
}

}  // namespace

TEST_CASE(
    "two DEM spheres off-centre with friction conserve linear and angular momentum, spin "
    "included",
    "[dem][dem_sphere]") {
  // Unequal radii and densities, spinning, meeting 60 degrees off-centre, away from the origin.
  const double ra = 0.004, rb = 0.006, offset = (ra + rb) * std::sin(60 * std::numbers::pi / 180);
  const Vec3 base(0.03, -0.02, 0.05);
  const auto dir = fresh_dir("dem-collision");
  std::string text = "bodies:\n";
  text += dem_sphere_entry("a", base, ra, Vec3(4, 0.5, 0), Vec3(50, -120, 300));
  text += dem_sphere_entry("b", base + Vec3(0.5 * (ra + rb) + 1e-5, offset, 0.001), rb,
                           Vec3(-3, 0, 0.2), Vec3(-200, 80, 0), 7800);
  text += hertz_mindlin_contact(0.8, 0.4);
  text += "time: {end: 5e-4}\n";
  Scene scene = load_scene(write_file(dir / "case.yaml", text));
  const Drift d = run_and_watch(scene);
  INFO("momentum drift " << d.momentum << ", angular momentum drift " << d.angular
                         << ", a's spin change " << d.spin_change.transpose() << " rad/s");
  CHECK(d.momentum < 1e-12);
  CHECK(d.angular < 1e-12);
  // Friction spun the spheres: the conservation holds with real spin exchanged.
  CHECK(d.spin_change.norm() > 10);
}

TEST_CASE(
    "a DEM sphere striking a free rigid body of points conserves momentum and angular "
    "momentum",
    "[dem][dem_sphere]") {
  const double radius = 0.003;
  const auto dir = fresh_dir("dem-rigid");
  std::string text = "bodies:\n";
  text += dem_sphere_entry("ball", Vec3(0.0021, 0.0013, 0.0051 + radius), radius,
                           Vec3(1.5, 0.3, -2), Vec3(0, 0, 150));
  text +=
      "  - {name: block, rigid: {motion: free, density: 2500, youngs_modulus: 70e9, "
      "poisson_ratio: 0.25}, geometry: {type: box, min: [-0.005, -0.005, -0.005], max: [0.005, "
      "0.005, 0.005]}, spacing: 0.001}\n";
  text += hertz_mindlin_contact(0.8, 0.4);
  text += "time: {end: 5e-4}\n";
  Scene scene = load_scene(write_file(dir / "case.yaml", text));
  const Drift d = run_and_watch(scene);
  INFO("momentum drift " << d.momentum << ", angular momentum drift " << d.angular
                         << ", the ball's spin change " << d.spin_change.transpose());
  CHECK(d.momentum < 1e-12);
  CHECK(d.angular < 1e-12);
  CHECK(d.spin_change.norm() > 10);
  // The block was pushed down and set turning.
  CHECK(scene.bodies[1].rigid->velocity().z() < 0);
  CHECK(scene.bodies[1].rigid->angular_velocity().norm() > 0);
}

TEST_CASE("two unequal DEM spheres touch at R_a + R_b and push with Hertz's R* and m*",
          "[dem][dem_sphere]") {
  // Head-on, no friction: the Hertz contact time 2.87 (m*^2 / (R* E*^2 v))^(1/5) (undamped;
  // e = 1 here) and the first contact at a centre distance R_a + R_b.
  const double ra = 0.002, rb = 0.005, v = 2;
  const auto dir = fresh_dir("dem-hertz-pair");
  std::string text = "bodies:\n";
  text += dem_sphere_entry("a", Vec3::Zero(), ra, Vec3(v, 0, 0));
  text += dem_sphere_entry("b", Vec3(ra + rb + 1e-6, 0, 0), rb, Vec3::Zero());
  text += hertz_mindlin_contact(1.0, 0);
  text += "time: {end: 1e-4}\n";
  Scene scene = load_scene(write_file(dir / "case.yaml", text));
  Simulation sim(scene);
  double first = -1, last = -1, gap_at_first = 0;
  while (sim.step() < sim.planned_steps()) {
    sim.advance(false);
    const bool touching = sim.contact()->statistics().points_in_contact > 0;
    if (touching && first < 0) {
      first = sim.time();
      gap_at_first = (scene.bodies[1].rigid->centre() - scene.bodies[0].rigid->centre()).norm();
    }
    if (first >= 0 && !touching) {
      last = sim.time();
      break;
    }
  }
  REQUIRE(last > 0);
  const double dt = sim.step_choice().dt;
  const double ma = kGlassDensity * 4.0 / 3 * std::numbers::pi * std::pow(ra, 3);
  const double mb = kGlassDensity * 4.0 / 3 * std::numbers::pi * std::pow(rb, 3);
  const double m_star = ma * mb / (ma + mb), r_star = ra * rb / (ra + rb);
  const double e_star = kGlassModulus / (2 * (1 - kGlassPoisson * kGlassPoisson));
  const double hertz = 2.868 * std::pow(m_star * m_star / (r_star * e_star * e_star * v), 0.2);
  INFO("contact from " << first << " s to " << last << " s (dt " << dt << "), Hertz " << hertz
                       << " s; centres " << gap_at_first << " m apart at first contact");
  CHECK(gap_at_first < ra + rb);
  CHECK(gap_at_first > ra + rb - v * dt);
  CHECK(last - first == Approx(hertz).margin(2 * dt).epsilon(0.01));
  // Elastic and frictionless: the velocities of a one-dimensional elastic collision.
  const double va = (ma - mb) / (ma + mb) * v, vb = 2 * ma / (ma + mb) * v;
  CHECK(scene.bodies[0].rigid->velocity().x() == Approx(va).epsilon(0.002));
  CHECK(scene.bodies[1].rigid->velocity().x() == Approx(vb).epsilon(0.002));
}
