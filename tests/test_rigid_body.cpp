// Rigid motion against mechanics: mass and inertia are the sums over the points, a constant
// force gives v = F t / M, a torque-free spinning body keeps its angular momentum and its energy,
// a torque changes L by tau dt, and a prescribed motion puts every point where the imposed
// translation and rotation say.
#include <catch2/catch.hpp>
#include <random>

#include "src/engine/rigid_body.hpp"

using namespace ckpd;

namespace {

// An irregular cloud of points: a body whose inertia is not isotropic.
Body cloud(unsigned seed, std::size_t n = 40) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Vec3> x;
  std::vector<double> v;
  for (std::size_t i = 0; i < n; ++i) {
    x.emplace_back(2 * u(rng), u(rng), 0.5 * u(rng));
    v.push_back(0.5 + 0.25 * (u(rng) + 1));
  }
  return make_point_set("cloud", 3, std::move(x), std::move(v), 1000);
}

double kinetic(const Body& b) {
  double e = 0;
  for (std::size_t i = 0; i < b.size(); ++i)
    e += 0.5 * b.density * b.volume[i] * b.velocity[i].squaredNorm();
  return e;
}

Vec3 angular_momentum(const Body& b, const Vec3& about) {
  Vec3 l = Vec3::Zero();
  for (std::size_t i = 0; i < b.size(); ++i)
    l += b.density * b.volume[i] * (b.current_position(i) - about).cross(b.velocity[i]);
  return l;
}

}  // namespace

TEST_CASE("a free rigid body under a constant force gains F t / M and no spin", "[rigid_body]") {
  Body body = cloud(1);
  RigidMotion motion(body, RigidMotion::Kind::free, Vec3::Zero(), Vec3::Zero());
  double mass = 0;
  for (double v : body.volume) mass += body.density * v;
  CHECK(motion.mass() == Approx(mass).epsilon(1e-14));
  motion.initialise(body);
  const Vec3 force(3, -1, 2);
  const double dt = 1e-3;
  auto load = [&] {
    // Force density proportional to volume: total F, no torque about the mass centre.
    for (std::size_t i = 0; i < body.size(); ++i)
      body.force_density[i] = force / (mass / body.density);
  };
  load();
  for (int s = 0; s < 100; ++s) {
    motion.first_half(body, s * dt, dt);
    load();
    motion.second_half(body, (s + 1) * dt, dt);
  }
  CHECK((motion.velocity() - force * 100 * dt / mass).norm() < 1e-12 * force.norm());
  CHECK(motion.angular_velocity().norm() < 1e-12);
}

TEST_CASE("a torque-free spinning rigid body keeps its angular momentum and energy",
          "[rigid_body]") {
  Body body = cloud(2);
  RigidMotion motion(body, RigidMotion::Kind::free, Vec3(0.1, 0, 0), Vec3(0.3, 2.0, -0.7));
  motion.initialise(body);
  const Vec3 c0 = motion.centre();
  const Vec3 l0 = angular_momentum(body, motion.centre());
  const double e0 = kinetic(body);
  const double dt = 1e-4;
  for (int s = 0; s < 2000; ++s) {
    motion.first_half(body, s * dt, dt);
    motion.second_half(body, (s + 1) * dt, dt);
  }
  CHECK((angular_momentum(body, motion.centre()) - l0).norm() < 1e-10 * l0.norm());
  CHECK(kinetic(body) == Approx(e0).epsilon(1e-3));  // the rotation update is first order
  CHECK((motion.centre() - c0 - Vec3(0.1, 0, 0) * 2000 * dt).norm() < 1e-12);
}

TEST_CASE("a force off the mass centre changes the angular momentum by its torque",
          "[rigid_body]") {
  Body body = cloud(3);
  RigidMotion motion(body, RigidMotion::Kind::free, Vec3::Zero(), Vec3::Zero());
  motion.initialise(body);
  const Vec3 f(0, 0, 5);
  const Vec3 lever = body.current_position(0) - motion.centre();
  const double dt = 1e-5;
  std::fill(body.force_density.begin(), body.force_density.end(), Vec3::Zero());
  body.force_density[0] = f / body.volume[0];
  motion.first_half(body, 0, dt);
  motion.second_half(body, dt, dt);  // the same force density at both kicks
  const Vec3 l = angular_momentum(body, motion.centre());
  // L = tau dt to first order in the rotation of one step.
  CHECK((l - lever.cross(f) * dt).norm() < 1e-4 * lever.cross(f).norm() * dt);
}

TEST_CASE("a prescribed rigid motion places every point at the imposed pose", "[rigid_body]") {
  Body body = cloud(4);
  const Vec3 v(1, 2, 3), omega(0, 0, 4);
  RigidMotion motion(body, RigidMotion::Kind::prescribed, v, omega);
  motion.initialise(body);
  const Vec3 c0 = motion.centre();
  const double dt = 1e-3;
  for (int s = 0; s < 50; ++s) {
    motion.first_half(body, s * dt, dt);
    motion.second_half(body, (s + 1) * dt, dt);
  }
  const double t = 50 * dt;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(4 * t, Vec3::UnitZ()).toRotationMatrix();
  for (std::size_t i = 0; i < body.size(); ++i) {
    const Vec3 expected = c0 + t * v + R * (body.reference_position[i] - c0);
    REQUIRE((body.current_position(i) - expected).norm() < 1e-12);
    REQUIRE((body.velocity[i] - (v + omega.cross(body.current_position(i) - c0 - t * v))).norm() <
            1e-9);
  }
}
