// Normal DEM laws against their closed forms (derived in contact/laws/*.hpp, recomputed here from
// the textbook formulae): two one-point rigid spheres under linear_dashpot rebound with the
// coefficient of restitution e and stay in contact for pi / (omega_0 sqrt(1 - zeta^2)); under
// hertz_mindlin the force follows Hertz's 4/3 E* sqrt(R*) delta^(3/2), the deepest overlap and
// the contact time Hertz's impact solution. The dashpot's energy is booked as contact_damping
// and the balance stays closed.
#include <catch2/catch.hpp>
#include <cmath>

#include "dem_fixtures.hpp"

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
