// Tangential history with Coulomb friction against rigid-body mechanics:
// - oblique impact of a spinning-capable rigid ball on a fixed wall (Maw, Barber and Fawcett
//   1976; Kharaz, Gorham and Salman 2001): in the sliding regime the tangential rebound velocity
//   and the spin are the Coulomb rigid-body ones, v_t' = v_t - mu (1 + e) v_n and
//   omega' = mu (1 + e) m v_n R / I, and sliding stops during contact below the predicted
//   angle tan(theta*) = mu (1 + e) (1 + m R^2 / I);
// - a block on an inclined plane sticks below atan(mu) and slides with g (sin a - mu cos a);
// - two free rigid balls in a glancing frictional collision conserve linear and angular
//   momentum (spin included) to rounding;
// - friction's dissipation is booked (contact_friction) and the balance stays closed.
#include <omp.h>

#include <catch2/catch.hpp>
#include <cmath>

#include "base/parallel_policy.hpp"
#include "dem_fixtures.hpp"

using namespace ckpd;
using namespace ckpd::testing;

namespace {

constexpr double kDx = 1e-3, kBall = 3e-3, kLc = 0.5e-3, kHorizon = 1e-3;

Eigen::Matrix3d inertia_of(const Body& b, const Vec3& centre) {
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < b.size(); ++i) {
    const Vec3 r = b.reference_position[i] - centre;
    inertia += b.density * b.volume[i] *
               (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
  }
  return inertia;
}

struct Rebound {
  Vec3 velocity, spin;
  double mass = 0, inertia = 0;  // about the y axis
  double friction_dissipated = 0, balance_error = 0, initial_kinetic = 0;
};

// The lattice ball falls on the wall z = 0 at speed v, `angle` from the normal, in the x-z plane.
Rebound oblique(double angle, double mu, double e) {
  const double v = 1.0;
  const double mass = kDemDensity * kDx * kDx * kDx * lattice_ball(Vec3::Zero(), kBall, kDx).size();
  // Stiff enough that the deepest overlap is 1 % of l_c: m v^2 = k delta^2.
  const double k = mass * v * v / std::pow(0.01 * kLc, 2);
  const double omega = std::sqrt(k / mass);
  const double dt = M_PI / omega / 2000;
  const Vec3 velocity(v * std::sin(angle), 0, -v * std::cos(angle));
  const Vec3 centre(0, 0, kBall + kLc + 3 * v * dt);
  std::vector<SceneBody> bodies;
  bodies.push_back(
      rigid_points("ball", lattice_ball(centre, kBall, kDx), kDx * kDx * kDx, velocity, kDx));
  bodies.push_back(flat_wall(0.05));
  Scene scene =
      dem_scene(std::move(bodies),
                dem_settings("linear_dashpot", {{"restitution", {e}}, {"friction", {mu}}}, kLc,
                             ccon_for_spring(k, kDx * kDx * kDx, kHorizon), kHorizon),
                dt, 100000);
  Simulation sim(scene);
  const RigidMotion& ball = *scene.bodies[0].rigid;
  Rebound r;
  r.mass = ball.mass();
  r.inertia = inertia_of(scene.bodies[0].body, centre)(1, 1);
  r.initial_kinetic = sim.energies().kinetic;
  bool met = false;
  for (int step = 0; step < 20000; ++step) {
    sim.advance(true);
    const bool now = sim.contact()->statistics().points_in_contact > 0;
    r.balance_error = std::max(r.balance_error, std::abs(sim.energies().balance_error));
    if (met && !now) break;
    met = met || now;
  }
  REQUIRE(met);
  r.velocity = ball.velocity();
  r.spin = ball.angular_velocity();
  r.friction_dissipated = sim.energies().contact_friction;
  return r;
}

}  // namespace

TEST_CASE("oblique impact, sliding regime: tangential rebound and spin of Coulomb's rigid body",
          "[contact][dem][friction]") {
  const double mu = 0.1, e = 0.9, v = 1.0;
  const Rebound probe = oblique(0.8, mu, e);
  const double lever = kBall + kLc;  // centre to wall when the pole touches (overlap << l_c)
  const double critical =
      std::atan(mu * (1 + e) * (1 + probe.mass * lever * lever / probe.inertia));
  for (double angle : {1.2 * critical, 1.5 * critical, 1.3}) {
    const Rebound r = oblique(angle, mu, e);
    const double vn = v * std::cos(angle), vt = v * std::sin(angle);
    const double tangential = vt - mu * (1 + e) * vn;
    const double spin = mu * (1 + e) * r.mass * vn * lever / r.inertia;
    INFO("angle " << angle << " (critical " << critical << "): v_t' " << r.velocity.x()
                  << " against " << tangential << ", spin " << r.spin.y() << " against " << spin);
    CHECK(r.velocity.x() == Approx(tangential).epsilon(0.02));
    CHECK(r.spin.y() == Approx(spin).epsilon(0.02));
    CHECK(r.velocity.z() == Approx(e * vn).epsilon(0.01));
    // Sliding dissipated energy; the balance holds to a small part of it.
    CHECK(r.friction_dissipated > 0);
    CHECK(r.balance_error < 0.02 * (r.friction_dissipated + r.initial_kinetic * (1 - e * e)));
  }
}

TEST_CASE("oblique impact: the contact point stops slipping below the predicted transition angle",
          "[contact][dem][friction]") {
  const double mu = 0.1, e = 0.9, v = 1.0;
  const Rebound probe = oblique(0.8, mu, e);
  const double lever = kBall + kLc;
  const double ratio = 1 + probe.mass * lever * lever / probe.inertia;
  const double critical = std::atan(mu * (1 + e) * ratio);
  // The contact point's slip velocity after the impact, u' = v_t' - R omega': Coulomb's rigid
  // body slides throughout above the transition, u' = v_n (tan theta - tan theta*) > 0; below
  // it the slip stops during contact (u' = 0 without tangential compliance; the spring's
  // recoil then turns it back, u' < 0, Maw, Barber and Fawcett).
  auto final_slip = [&](double angle) {
    const Rebound r = oblique(angle, mu, e);
    return r.velocity.x() - lever * r.spin.y();
  };
  for (double factor : {1.1, 1.25}) {
    const double angle = factor * critical;
    const double expected = v * std::cos(angle) * (std::tan(angle) - std::tan(critical));
    const double slip = final_slip(angle);
    INFO("angle " << angle << " (critical " << critical << "): slip " << slip << " against "
                  << expected);
    CHECK(slip == Approx(expected).epsilon(0.05));
  }
  for (double factor : {0.9, 0.6}) {
    const double slip = final_slip(factor * critical);
    INFO(factor << " x critical: slip " << slip);
    CHECK(slip < 0.01 * v * std::sin(factor * critical));
  }
}

TEST_CASE("a block on an inclined plane sticks below atan(mu) and slides with g (sin a - mu cos a)",
          "[contact][dem][friction]") {
  const double mu = 0.5, g = 9.81, volume = kDx * kDx * kDx, k = 100;
  const double mass = 4 * kDemDensity * volume;
  const double omega = std::sqrt(4 * k / mass), dt = 2 * M_PI / omega / 100;
  for (double degrees : {20.0, 35.0}) {
    const double a = degrees * M_PI / 180;
    // The wall stays level; gravity tilts by a (the plane's frame).
    const Vec3 gravity(g * std::sin(a), 0, -g * std::cos(a));
    const double settled = mass * g * std::cos(a) / (4 * k);  // overlap at rest
    std::vector<Vec3> corners;
    for (double x : {-1.0, 1.0})
      for (double y : {-1.0, 1.0}) corners.emplace_back(x * kDx, y * kDx, kLc - settled);
    std::vector<SceneBody> bodies;
    bodies.push_back(rigid_points("block", corners, volume, Vec3::Zero(), kDx));
    bodies.back().conditions.push_back(
        std::make_unique<UniformAcceleration>(bodies.back().body, gravity));
    bodies.push_back(flat_wall(1.0));
    Scene scene =
        dem_scene(std::move(bodies),
                  dem_settings("linear_dashpot", {{"restitution", {0.3}}, {"friction", {mu}}}, kLc,
                               ccon_for_spring(k, volume, kHorizon), kHorizon),
                  dt, 1000000);
    Simulation sim(scene);
    const RigidMotion& block = *scene.bodies[0].rigid;
    const double t1 = 0.01, t2 = 0.03;
    double v1 = 0;
    while (sim.time() < t1) sim.advance(false);
    v1 = block.velocity().x();
    const double x1 = block.centre().x();
    while (sim.time() < t2) sim.advance(false);
    const double t = sim.time() - t1;
    const double acceleration = (block.velocity().x() - v1) / t;
    INFO(degrees << " degrees: acceleration " << acceleration << ", moved "
                 << block.centre().x() - x1);
    CHECK(std::abs(block.centre().z() - corners[0].z()) < 0.1 * kLc);  // still on the plane
    if (std::tan(a) < mu) {
      // Stuck: it moves no more than the tangential spring's give, far below sliding's.
      CHECK(std::abs(block.centre().x() - x1) < 1e-2 * 0.5 * g * std::sin(a) * t * t);
    } else {
      CHECK(acceleration == Approx(g * (std::sin(a) - mu * std::cos(a))).epsilon(0.02));
    }
  }
}

TEST_CASE(
    "free rigid balls in a glancing frictional collision conserve linear and angular momentum",
    "[contact][dem][friction]") {
  const double volume = kDx * kDx * kDx;
  for (const char* law : {"linear_dashpot", "hertz_mindlin"}) {
    std::vector<SceneBody> bodies;
    const double r = 2 * kDx;
    bodies.push_back(rigid_points("a", lattice_ball(Vec3(-r - 0.4 * kLc, 0.3 * r, 0.1 * r), r, kDx),
                                  volume, Vec3(2, 0.3, 0), kDx, RigidMotion::Kind::free,
                                  Vec3(0, 0, 40)));
    bodies.push_back(rigid_points("b", lattice_ball(Vec3(r + 0.4 * kLc, -0.3 * r, 0), r, kDx),
                                  volume, Vec3(-1, 0, 0.2), kDx));
    std::map<std::string, std::vector<double>> parameters{{"restitution", {0.7}},
                                                          {"friction", {0.4}}};
    if (std::string(law) == "hertz_mindlin") {
      parameters["youngs_modulus"] = {1e9};
      parameters["poisson_ratio"] = {0.3};
    }
    const double stiffness = ccon_for_spring(1e5, volume, kHorizon);
    Scene scene =
        dem_scene(std::move(bodies), dem_settings(law, parameters, 2.2 * kLc, stiffness, kHorizon),
                  2e-7, 3000);
    Simulation sim(scene);
    auto momenta = [&](Vec3& p, Vec3& l) {
      p = l = Vec3::Zero();
      for (const SceneBody& sb : scene.bodies) {
        const RigidMotion& m = *sb.rigid;
        p += m.mass() * m.velocity();
        l += m.centre().cross(m.mass() * m.velocity()) + m.state().angular_momentum;
      }
    };
    Vec3 p0, l0, p, l;
    momenta(p0, l0);
    const double p_scale = 2 * scene.bodies[1].rigid->mass() + scene.bodies[0].rigid->mass() * 2;
    const double l_scale = l0.norm() + p_scale * 4 * kDx;
    double worst_p = 0, worst_l = 0;
    while (sim.step() < sim.planned_steps()) {
      sim.advance(false);
      momenta(p, l);
      worst_p = std::max(worst_p, (p - p0).norm() / p_scale);
      worst_l = std::max(worst_l, (l - l0).norm() / l_scale);
    }
    INFO(law << ": momentum error " << worst_p << ", angular momentum error " << worst_l);
    CHECK(sim.contact()->statistics().points_in_contact_peak > 0);
    CHECK(sim.energies().contact_friction > 0);
    // The collision changed the spins (friction acted) and the momenta held.
    CHECK((scene.bodies[1].rigid->angular_velocity()).norm() > 1e-3);
    CHECK(worst_p < 1e-12);
    CHECK(worst_l < 1e-12);
  }
}

TEST_CASE("DEM contact with friction gives the same bits on one and two threads, loops parallel",
          "[contact][dem][friction]") {
  // Two lattice balls of free rigid points against each other (point pairs, springs kept by the
  // first end) and a wall (springs per point), every loop parallel.
  const ScopedParallelThresholds every_loop_parallel(0);
  const int before = omp_get_max_threads();
  const double volume = kDx * kDx * kDx;
  std::vector<Vec3> state[2];
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    std::vector<SceneBody> bodies;
    bodies.push_back(rigid_points("a", lattice_ball(Vec3(-2.2e-3, 0, 2.3e-3), 2 * kDx, kDx), volume,
                                  Vec3(2, 0, -1), kDx));
    bodies.push_back(rigid_points("b", lattice_ball(Vec3(2.2e-3, 0.5e-3, 2.3e-3), 2 * kDx, kDx),
                                  volume, Vec3(-2, 0, -1), kDx));
    bodies.push_back(flat_wall(0.05));
    Scene scene =
        dem_scene(std::move(bodies),
                  dem_settings("linear_dashpot", {{"restitution", {0.5}}, {"friction", {0.3}}},
                               1.1 * kLc, ccon_for_spring(1e5, volume, kHorizon), kHorizon),
                  2e-7, 800);
    Simulation sim(scene);
    while (sim.step() < sim.planned_steps()) sim.advance(false);
    REQUIRE(sim.energies().contact_friction > 0);
    for (const SceneBody& sb : scene.bodies) {
      state[threads - 1].push_back(sb.rigid->velocity());
      state[threads - 1].push_back(sb.rigid->state().angular_momentum);
    }
    state[threads - 1].push_back(Vec3(sim.energies().contact_damping,
                                      sim.energies().contact_friction, sim.energies().contact));
  }
  omp_set_num_threads(before);
  REQUIRE(state[0] == state[1]);
}
