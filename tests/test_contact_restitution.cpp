// Normal DEM laws against their closed forms (derived in contact/laws/*.hpp, recomputed here from
// the textbook formulae): two one-point rigid spheres under linear_dashpot rebound with the
// coefficient of restitution e and stay in contact for pi / (omega_0 sqrt(1 - zeta^2)); under
// hertz_mindlin the force follows Hertz's 4/3 E* sqrt(R*) delta^(3/2), the deepest overlap and
// the contact time Hertz's impact solution. The dashpot's energy is booked as contact_damping
// and the balance stays closed.
#include <catch2/catch.hpp>
#include <cmath>

#include "contact/laws/hertz_mindlin.hpp"
#include "dem_fixtures.hpp"
#include "src/engine/contact_coupling.hpp"

using namespace ckpd;
using namespace ckpd::testing;

namespace {

constexpr double kVolume = 1e-9, kLc = 1e-3, kHorizon = 1e-3, kSpring = 1e4;  // SI

struct Impact {
  double restitution = 0;  // separation speed / approach speed
  double duration = 0;     // time with a point pair closer than l_c
  double deepest = 0;      // largest overlap l_c - r
  double largest_balance_error = 0;
  double damping = 0;      // booked by the dashpot
  double energy_lost = 0;  // initial - final kinetic energy
};

// Two equal one-point spheres closing at 2 v0 along x, stepped until they have parted.
Impact head_on(ContactSettings contact, double dt, double v0) {
  std::vector<SceneBody> bodies;
  bodies.push_back(
      rigid_points("a", {Vec3(-0.5 * kLc - 2 * v0 * dt, 0, 0)}, kVolume, Vec3(v0, 0, 0)));
  bodies.push_back(
      rigid_points("b", {Vec3(0.5 * kLc + 2 * v0 * dt, 0, 0)}, kVolume, Vec3(-v0, 0, 0)));
  Scene scene = dem_scene(std::move(bodies), std::move(contact), dt, 1000000);
  Simulation sim(scene);
  const RigidMotion& a = *scene.bodies[0].rigid;
  const RigidMotion& b = *scene.bodies[1].rigid;
  const double e0 = sim.energies().kinetic;
  Impact out;
  long long touching = 0;
  bool met = false;
  for (int step = 0; step < 200000; ++step) {
    sim.advance(true);
    const bool now = sim.contact()->statistics().points_in_contact > 0;
    touching += now;
    met = met || now;
    const double r = (b.centre() - a.centre()).norm();
    out.deepest = std::max(out.deepest, kLc - r);
    out.largest_balance_error =
        std::max(out.largest_balance_error, std::abs(sim.energies().balance_error) / e0);
    if (met && !now) break;
  }
  out.restitution = (b.velocity().x() - a.velocity().x()) / (2 * v0);
  out.duration = static_cast<double>(touching) * dt;
  out.damping = sim.energies().contact_damping;
  out.energy_lost = e0 - sim.energies().kinetic;
  return out;
}

}  // namespace

TEST_CASE("linear_dashpot: restitution equals e and the contact lasts pi / omega_d",
          "[contact][dem][restitution]") {
  const double m = kDemDensity * kVolume, reduced = m / 2;
  const double omega0 = std::sqrt(kSpring / reduced);
  for (double e : {0.3, 0.6, 0.9}) {
    const double zeta = -std::log(e) / std::sqrt(M_PI * M_PI + std::log(e) * std::log(e));
    const double duration = M_PI / (omega0 * std::sqrt(1 - zeta * zeta));
    const double dt = duration / 2000;
    const Impact r = head_on(dem_settings("linear_dashpot", {{"restitution", {e}}}, kLc,
                                          ccon_for_spring(kSpring, kVolume, kHorizon), kHorizon),
                             dt, 1.0);
    INFO("e = " << e << ": measured " << r.restitution << ", duration " << r.duration
                << " s against " << duration << " s, balance error " << r.largest_balance_error);
    CHECK(r.restitution == Approx(e).epsilon(0.01));
    CHECK(r.duration == Approx(duration).epsilon(0.01));
    // The kinetic energy lost is what the dashpot booked (the rest of the balance: integration).
    CHECK(r.damping == Approx(r.energy_lost).epsilon(0.01));
    CHECK(r.largest_balance_error < 0.01);
  }
}

TEST_CASE("hertz_mindlin: Hertz's force-overlap law, deepest overlap and contact time",
          "[contact][dem][hertz]") {
  const double young = 200e9, poisson = 0.3;
  const double modulus = 1 / (2 * (1 - poisson * poisson) / young);  // E*: two equal sides
  const double radius = kLc / 4;                                     // R*: two spheres of l_c/2
  const ContactSettings elastic = dem_settings(
      "hertz_mindlin",
      {{"restitution", {1.0}}, {"youngs_modulus", {young}}, {"poisson_ratio", {poisson}}}, kLc);

  SECTION("force against overlap, points held still") {
    for (double overlap : {1e-7, 1e-6, 1e-5, 1e-4}) {
      std::vector<SceneBody> bodies;
      bodies.push_back(
          rigid_points("a", {Vec3(-0.5 * (kLc - overlap), 0, 0)}, kVolume, Vec3::Zero()));
      bodies.push_back(
          rigid_points("b", {Vec3(0.5 * (kLc - overlap), 0, 0)}, kVolume, Vec3::Zero()));
      Scene scene = dem_scene(std::move(bodies), elastic, 1e-9, 1);
      Simulation sim(scene);  // the first evaluation: forces at rest
      const double f = scene.bodies[1].body.force_density[0].x() * kVolume;
      const double hertz = 4.0 / 3 * modulus * std::sqrt(radius) * std::pow(overlap, 1.5);
      CHECK(f == Approx(hertz).epsilon(0.01));
      CHECK(scene.bodies[0].body.force_density[0].x() * kVolume == -f);
      // U = 8/15 E* sqrt(R*) delta^(5/2)
      CHECK(sim.energies().contact ==
            Approx(8.0 / 15 * modulus * std::sqrt(radius) * std::pow(overlap, 2.5)).epsilon(1e-9));
    }
  }
  SECTION("impact: deepest overlap and contact time, elastic") {
    const double v0 = 1.0, reduced = kDemDensity * kVolume / 2;
    // Energy: m* (2 v0)^2 / 2 = 8/15 E* sqrt(R*) delta^(5/2).
    const double deepest =
        std::pow(15 * reduced * 4 * v0 * v0 / (16 * modulus * std::sqrt(radius)), 0.4);
    // t_c = 2 delta_max / v int_0^1 (1 - x^(5/2))^(-1/2) dx, the integral by the midpoint rule.
    double integral = 0;
    const int n = 200000;
    for (int k = 0; k < n; ++k) integral += 1 / std::sqrt(1 - std::pow((k + 0.5) / n, 2.5)) / n;
    const double duration = 2 * deepest / (2 * v0) * integral;
    const Impact r = head_on(elastic, duration / 4000, v0);
    INFO("deepest " << r.deepest << " against " << deepest << ", duration " << r.duration
                    << " against " << duration);
    CHECK(r.deepest == Approx(deepest).epsilon(0.01));
    CHECK(r.duration == Approx(duration).epsilon(0.01));
    CHECK(r.restitution == Approx(1).epsilon(0.005));
  }
}

namespace {

// A one-point rigid sphere with the elastic constants of its material.
SceneBody elastic_point(const std::string& name, const Vec3& at, const Vec3& velocity, double E,
                        double nu) {
  SceneBody sb = rigid_points(name, {at}, kVolume, velocity);
  sb.elastic = ElasticConstants{E, nu};
  return sb;
}

double contact_time(double modulus, double radius, double mass, double speed) {
  return hertz::duration_factor() * hertz::max_overlap(modulus, radius, mass, speed) / speed;
}

}  // namespace

TEST_CASE("hertz_mindlin takes E and nu from both bodies: Hertz's force and contact time",
          "[contact][dem][hertz]") {
  const double E1 = 200e9, nu1 = 0.3, E2 = 70e9, nu2 = 0.33;
  // E* of two different sides, the textbook way.
  const double modulus = 1 / ((1 - nu1 * nu1) / E1 + (1 - nu2 * nu2) / E2);
  const ContactSettings law = dem_settings("hertz_mindlin", {{"restitution", {1.0}}}, kLc);

  SECTION("force against overlap") {
    const double overlap = 1e-5;
    std::vector<SceneBody> bodies;
    bodies.push_back(elastic_point("a", Vec3(-0.5 * (kLc - overlap), 0, 0), Vec3::Zero(), E1, nu1));
    bodies.push_back(elastic_point("b", Vec3(0.5 * (kLc - overlap), 0, 0), Vec3::Zero(), E2, nu2));
    Scene scene = dem_scene(std::move(bodies), law, 1e-9, 1);
    Simulation sim(scene);
    const double f = scene.bodies[1].body.force_density[0].x() * kVolume;
    CHECK(f ==
          Approx(4.0 / 3 * modulus * std::sqrt(kLc / 4) * std::pow(overlap, 1.5)).epsilon(1e-9));
  }
  SECTION("two spheres: contact time") {
    const double v0 = 1.0, reduced = kDemDensity * kVolume / 2;
    const double duration = contact_time(modulus, kLc / 4, reduced, 2 * v0);
    const double dt = duration / 4000;
    std::vector<SceneBody> bodies;
    bodies.push_back(
        elastic_point("a", Vec3(-0.5 * kLc - 2 * v0 * dt, 0, 0), Vec3(v0, 0, 0), E1, nu1));
    bodies.push_back(
        elastic_point("b", Vec3(0.5 * kLc + 2 * v0 * dt, 0, 0), Vec3(-v0, 0, 0), E2, nu2));
    Scene scene = dem_scene(std::move(bodies), law, dt, 100000);
    Simulation sim(scene);
    long long touching = 0;
    bool met = false;
    for (int step = 0; step < 100000; ++step) {
      sim.advance(false);
      const bool now = sim.contact()->statistics().points_in_contact > 0;
      touching += now;
      if (met && !now) break;
      met = met || now;
    }
    CHECK(static_cast<double>(touching) * dt == Approx(duration).epsilon(0.01));
    CHECK(scene.bodies[1].rigid->velocity().x() == Approx(v0).epsilon(0.005));
  }
  SECTION("a sphere on a mesh wall: contact time with the wall's own E and nu") {
    const double v0 = 0.5, mass = kDemDensity * kVolume;
    const double wall_modulus = 1 / ((1 - nu1 * nu1) / E1 + (1 - nu2 * nu2) / E2);
    const double duration = contact_time(wall_modulus, kLc, mass, v0);  // R* = l_c on a wall
    const double dt = duration / 4000;
    std::vector<SceneBody> bodies;
    bodies.push_back(
        elastic_point("ball", Vec3(0, 0, kLc + 2 * v0 * dt), Vec3(0, 0, -v0), E1, nu1));
    bodies.push_back(flat_wall(0.01));
    bodies.back().elastic = ElasticConstants{E2, nu2};
    Scene scene = dem_scene(std::move(bodies), law, dt, 100000);
    Simulation sim(scene);
    long long touching = 0;
    bool met = false;
    for (int step = 0; step < 100000; ++step) {
      sim.advance(false);
      const bool now = sim.contact()->statistics().points_in_contact > 0;
      touching += now;
      if (met && !now) break;
      met = met || now;
    }
    CHECK(static_cast<double>(touching) * dt == Approx(duration).epsilon(0.01));
    CHECK(scene.bodies[0].rigid->velocity().z() == Approx(v0).epsilon(0.005));
  }
  SECTION("the contact section's E and nu override the bodies'") {
    const double overlap = 1e-5;
    std::vector<SceneBody> bodies;
    bodies.push_back(elastic_point("a", Vec3(-0.5 * (kLc - overlap), 0, 0), Vec3::Zero(), E1, nu1));
    bodies.push_back(elastic_point("b", Vec3(0.5 * (kLc - overlap), 0, 0), Vec3::Zero(), E2, nu2));
    Scene scene = dem_scene(
        std::move(bodies),
        dem_settings("hertz_mindlin",
                     {{"restitution", {1.0}}, {"youngs_modulus", {1e9}}, {"poisson_ratio", {0.2}}},
                     kLc),
        1e-9, 1);
    Simulation sim(scene);
    const double given = 1 / (2 * (1 - 0.04) / 1e9);
    CHECK(scene.bodies[1].body.force_density[0].x() * kVolume ==
          Approx(4.0 / 3 * given * std::sqrt(kLc / 4) * std::pow(overlap, 1.5)).epsilon(1e-9));
  }
  SECTION("a rigid body without E and nu is refused, naming it") {
    std::vector<SceneBody> bodies;
    bodies.push_back(elastic_point("a", Vec3(-kLc, 0, 0), Vec3::Zero(), E1, nu1));
    bodies.push_back(rigid_points("b", {Vec3(kLc, 0, 0)}, kVolume, Vec3::Zero()));
    Scene scene = dem_scene(std::move(bodies), law, 1e-9, 1);
    CHECK_THROWS_WITH(scene.contact.law(contact_bodies(std::as_const(scene)), 0, 1),
                      Catch::Contains("body 'b', a rigid body: give `youngs_modulus` and "
                                      "`poisson_ratio` in its `rigid` section"));
  }
}
