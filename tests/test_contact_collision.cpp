// Collisions against mechanics the code does not define: conservation of momentum, mirror
// symmetry, no interpenetration, bouncing off a support, frictionless sliding, and the contact
// stiffness in the stable step (stable at the automatic step, unstable at three times it).
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <tuple>

#include "contact_fixtures.hpp"
#include "src/engine/contact_coupling.hpp"

using namespace ckpd;
using namespace ckpd::testing;

namespace {

constexpr double kRadius = 0.0025, kSpacing = 0.001, kContactRadius = 0.0005;

std::string two_spheres(const std::string& material, const std::string& time) {
  std::string text = material;
  text += "bodies:\n";
  text += sphere_body("left", "m", -0.0026, 0, 0, kRadius, kSpacing);
  text += sphere_body("right", "m", 0.0026, 0, 0, kRadius, kSpacing);
  text +=
      "conditions:\n"
      "  - {type: initial_velocity, body: left, value: [10, 1, 0]}\n"
      "  - {type: initial_velocity, body: right, value: [-10, 1, 0]}\n"
      "contact: {stiffness: 1.0e12, radius: 0.0005}\n";
  text += time;
  return text;
}

const char* kSteel =
    "materials:\n  m: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.25}\n";
// Soft enough that contact, not the bonds, limits the step: Ccon = 1000 GPa against E = 2 GPa.
const char* kSoft = "materials:\n  m: {density: 1200, youngs_modulus: 2e9, poisson_ratio: 0.25}\n";

double closest_approach(const Body& a, const Body& b) {
  double d2 = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = 0; j < b.size(); ++j)
      d2 = std::min(d2, (a.current_position(i) - b.current_position(j)).squaredNorm());
  return std::sqrt(d2);
}

Vec3 total_momentum(const Scene& scene) {
  Vec3 p = Vec3::Zero();
  for (const SceneBody& sb : scene.bodies) p += momentum(sb.body);
  return p;
}

Vec3 angular_momentum(const Scene& scene) {
  Vec3 l = Vec3::Zero();
  for (const SceneBody& sb : scene.bodies)
    for (std::size_t i = 0; i < sb.body.size(); ++i)
      l += sb.body.density * sb.body.volume[i] *
           sb.body.current_position(i).cross(sb.body.velocity[i]);
  return l;
}

}  // namespace

TEST_CASE("two equal elastic spheres in a head-on collision", "[contact][physics]") {
  Scene scene = scene_from_text("head-on", two_spheres(kSteel, "time: {end: 6.0e-5}\n"));
  Simulation sim(scene);
  const Body& left = scene.bodies[0].body;
  const Body& right = scene.bodies[1].body;
  const Vec3 p0 = total_momentum(scene);
  const double scale = momentum_scale(scene);
  double closest = std::numeric_limits<double>::infinity(), worst_momentum = 0;
  while (sim.step() < sim.planned_steps()) {
    sim.advance(false);
    worst_momentum = std::max(worst_momentum, (total_momentum(scene) - p0).norm() / scale);
    closest = std::min(closest, closest_approach(left, right));
  }
  INFO("momentum error " << worst_momentum << ", closest approach " << closest << " m");
  CHECK(worst_momentum < 1e-10);
  // They met, and no point came deeper than half the contact radius into the other's zone.
  CHECK(sim.contact()->statistics().points_in_contact_peak > 0);
  CHECK(closest > 0.5 * kContactRadius);
  CHECK(closest < kContactRadius);
  // They separate: apart now, the relative velocity reversed, no point of one past the other.
  CHECK(sim.contact()->statistics().points_in_contact == 0);
  const double separating = momentum(right).x() / right.mass() - momentum(left).x() / left.mass();
  CHECK(separating > 5);
  double left_front = -1, right_back = 1;
  for (std::size_t i = 0; i < left.size(); ++i)
    left_front = std::max(left_front, left.current_position(i).x());
  for (std::size_t i = 0; i < right.size(); ++i)
    right_back = std::min(right_back, right.current_position(i).x());
  CHECK(left_front < right_back);

  // Mirror symmetry in x = 0: each point of one sphere moves as the mirror image of its twin.
  std::map<std::tuple<long, long, long>, std::size_t> twin;
  auto key = [](const Vec3& X) {
    return std::make_tuple(std::lround(X.x() * 1e7), std::lround(X.y() * 1e7),
                           std::lround(X.z() * 1e7));
  };
  for (std::size_t j = 0; j < right.size(); ++j) twin[key(right.reference_position[j])] = j;
  double asymmetry = 0, largest = 0;
  for (std::size_t i = 0; i < left.size(); ++i) {
    const Vec3& X = left.reference_position[i];
    const auto it = twin.find(key(Vec3(-X.x(), X.y(), X.z())));
    REQUIRE(it != twin.end());
    const Vec3 u = left.displacement[i], w = right.displacement[it->second];
    asymmetry = std::max(asymmetry, (u - Vec3(-w.x(), w.y(), w.z())).norm());
    largest = std::max(largest, u.norm());
  }
  INFO("mirror asymmetry " << asymmetry << " m of displacements up to " << largest << " m");
  CHECK(asymmetry < 1e-9 * largest);
}

TEST_CASE("two 2D discs collide and separate with their momentum", "[contact][physics]") {
  // nu = 1/3 in plane stress makes C2 = 0 (bonds only): CKPD's two-neighbour force on a point is
  // the gradient of its own family's energy alone, not a pairwise force, and does not conserve
  // momentum by itself near surfaces (1e-5 here with nu = 0.3), whatever contact does.
  const char* text = R"(
materials:
  m: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.3333333333333333}
bodies:
  - {name: left, material: m, dimension: 2, geometry: {type: sphere, center: [-0.0026, 0.0003],
     radius: 0.0025}, spacing: 0.0005, horizon_ratio: 3.015}
  - {name: right, material: m, dimension: 2, geometry: {type: sphere, center: [0.0026, 0],
     radius: 0.0025}, spacing: 0.0005, horizon_ratio: 3.015}
conditions:
  - {type: initial_velocity, body: left, value: [10, 0]}
  - {type: initial_velocity, body: right, value: [-10, 0]}
contact: {stiffness: 1.0e12}
time: {end: 6.0e-5}
)";
  Scene scene = scene_from_text("discs", text);
  Simulation sim(scene);
  const Vec3 p0 = total_momentum(scene);
  const double scale = momentum_scale(scene);
  double worst = 0;
  while (sim.step() < sim.planned_steps()) {
    sim.advance(false);
    worst = std::max(worst, (total_momentum(scene) - p0).norm() / scale);
  }
  const Body& left = scene.bodies[0].body;
  const Body& right = scene.bodies[1].body;
  INFO("momentum error " << worst);
  CHECK(sim.contact()->statistics().points_in_contact_peak > 0);
  CHECK(sim.contact()->statistics().points_in_contact == 0);
  CHECK(worst < 1e-10);
  CHECK(momentum(right).x() / right.mass() - momentum(left).x() / left.mass() > 5);
  // Hit off-centre (left is 0.3 mm higher), they leave with opposite sideways velocities.
  CHECK(momentum(left).y() > 0);
  CHECK(momentum(right).y() < 0);
}

TEST_CASE("a sphere bounces off a fixed rigid support", "[contact][physics]") {
  std::string text = kSteel;
  text += "bodies:\n";
  text += sphere_body("ball", "m", 0, 0, 0.0022, kRadius, kSpacing);
  text +=
      "  - {name: floor, rigid: {motion: prescribed}, geometry: {type: box, min: [-0.006, "
      "-0.006, -0.002], max: [0.006, 0.006, 0]}, spacing: 0.001}\n"
      "conditions:\n"
      "  - {type: initial_velocity, body: ball, value: [0, 0, -5]}\n"
      "contact: {stiffness: 1.0e12, radius: 0.0008}\n"
      "time: {end: 1.5e-4}\n";
  Scene scene = scene_from_text("bounce", text);
  Simulation sim(scene);
  const Body& ball = scene.bodies[0].body;
  const Vec3 floor_centre = scene.bodies[1].rigid->centre();
  const double e0 = sim.energies().kinetic;
  double worst_balance = 0;
  while (sim.step() < sim.planned_steps()) {
    sim.advance(true);
    worst_balance = std::max(worst_balance, std::abs(sim.energies().balance_error) / e0);
  }
  const double vz = momentum(ball).z() / ball.mass();
  INFO("rebound " << vz << " m/s, energy balance error " << worst_balance);
  CHECK(sim.contact()->statistics().points_in_contact_peak > 0);
  CHECK(vz > 2.5);  // it bounced, keeping most of its speed (the rest rings in the sphere)
  CHECK(0.5 * ball.mass() * vz * vz < e0);
  CHECK(scene.bodies[1].rigid->centre() == floor_centre);
  CHECK(worst_balance < 5e-3);
}

TEST_CASE("a sphere thrown obliquely onto a support keeps its tangential momentum",
          "[contact][physics]") {
  // Frictionless contact: the impulse is normal to the support, so the tangential momentum
  // changes only by what the bumps of the support's lattice give. Those bumps shrink fast as l_c
  // spans more partner spacings: with l_c = 1.6 support spacings (here) the tangential change is
  // 0.3 % of the normal one; with l_c = 0.8 spacing it is 16 %, a coarse lattice acting as
  // roughness.
  std::string text = kSteel;
  text += "bodies:\n";
  text += sphere_body("ball", "m", 0, 0, 0.0022, kRadius, kSpacing);
  text +=
      "  - {name: floor, rigid: {motion: prescribed}, geometry: {type: box, min: [-0.008, "
      "-0.006, -0.002], max: [0.008, 0.006, 0]}, spacing: 0.0005}\n"
      "conditions:\n"
      "  - {type: initial_velocity, body: ball, value: [3, 0, -5]}\n"
      "contact: {stiffness: 1.0e12, radius: 0.0008}\n"
      "time: {end: 1.5e-4}\n";
  Scene scene = scene_from_text("oblique", text);
  Simulation sim(scene);
  const Body& ball = scene.bodies[0].body;
  const Vec3 p0 = momentum(ball);
  while (sim.step() < sim.planned_steps()) sim.advance(false);
  const Vec3 change = momentum(ball) - p0;
  INFO("momentum change " << change.transpose() << " kg m/s, before " << p0.transpose());
  CHECK(change.z() > 1.5 * std::abs(p0.z()));  // bounced
  CHECK(std::abs(change.x()) < 0.01 * change.z());
  CHECK(std::abs(change.y()) < 0.01 * change.z());
}

TEST_CASE("a free rigid sphere hitting an elastic one off-centre conserves momentum",
          "[contact][physics]") {
  std::string text = kSteel;
  text += "bodies:\n";
  text += sphere_body("ball", "m", 0.0026, 0.001, 0, kRadius, kSpacing);
  text +=
      "  - {name: rigid, material: m, rigid: {motion: free, velocity: [10, 0, 0]}, geometry: "
      "{type: sphere, center: [-0.0026, 0, 0], radius: 0.0025}, spacing: 0.001}\n"
      "contact: {stiffness: 1.0e12, radius: 0.0005}\n"
      "time: {end: 1.0e-4}\n";
  Scene scene = scene_from_text("rigid-free", text);
  Simulation sim(scene);
  const Vec3 p0 = total_momentum(scene), l0 = angular_momentum(scene);
  const double scale = momentum_scale(scene);
  const double e0 = sim.energies().kinetic;
  double worst_p = 0, worst_l = 0, worst_balance = 0;
  while (sim.step() < sim.planned_steps()) {
    sim.advance(true);
    worst_p = std::max(worst_p, (total_momentum(scene) - p0).norm() / scale);
    worst_l = std::max(worst_l, (angular_momentum(scene) - l0).norm() / (scale * kRadius));
    worst_balance = std::max(worst_balance, std::abs(sim.energies().balance_error) / e0);
  }
  const RigidMotion& rigid = *scene.bodies[1].rigid;
  INFO("momentum " << worst_p << ", angular momentum " << worst_l << ", energy " << worst_balance
                   << ", spin " << rigid.angular_velocity().transpose());
  CHECK(sim.contact()->statistics().points_in_contact_peak > 0);
  CHECK(worst_p < 1e-10);
  CHECK(worst_l < 1e-10);
  CHECK(worst_balance < 5e-3);
  // It handed on most of its momentum, and the lattice's uneven contact set it turning (the
  // angular momentum it took is what the check above balances).
  CHECK(rigid.velocity().x() < 5);
  CHECK(rigid.angular_velocity().norm() > 1);
}

TEST_CASE("stiff contact (Ccon = 1000 GPa) is stable at the automatic step", "[contact][physics]") {
  Scene scene = scene_from_text("stiff", two_spheres(kSoft, "time: {end: 1.2e-4}\n"));
  const double bonds_only = stable_step_with(scene.bodies[0].body, 0).dt;
  Simulation sim(scene);
  // Contact, not the bonds, sets the step here: three times the step is stable for the bonds.
  REQUIRE(sim.step_choice().estimate * 3 < bonds_only);
  const double e0 = sim.energies().kinetic;
  double worst = 0;
  while (sim.step() < sim.planned_steps()) {
    REQUIRE_NOTHROW(sim.advance(true));
    worst = std::max(worst, std::abs(sim.energies().balance_error) / e0);
  }
  const double after = std::abs(sim.energies().balance_error) / e0;
  INFO("energy balance error up to " << worst << " of the kinetic energy, " << after << " after");
  CHECK(sim.contact()->statistics().points_in_contact_peak > 0);
  CHECK(sim.contact()->statistics().points_in_contact == 0);  // through and out again
  // Stated tolerance: 3 % during the collision (measured 2.5 %), 1 % once apart (0.5 %).
  CHECK(worst < 0.03);
  CHECK(after < 0.01);
}

TEST_CASE("stiff contact at three times the automatic step trips the instability guard",
          "[contact][physics]") {
  Scene probe = scene_from_text("stiff-probe", two_spheres(kSoft, "time: {end: 1.2e-4}\n"));
  const double estimate = choose_time_step(probe).estimate;
  Scene scene = scene_from_text("stiff-3x", two_spheres(kSoft, "time: {end: 1.2e-4}\n"));
  scene.time.dt = 3 * estimate;
  scene.time.allow_unstable_dt = true;
  Simulation sim(scene);
  std::string message;
  long long first_contact = -1;
  try {
    while (sim.step() < sim.planned_steps()) {
      sim.advance(true);
      if (first_contact < 0 && sim.contact()->statistics().points_in_contact > 0)
        first_contact = sim.step();
    }
  } catch (const InstabilityError& e) {
    message = e.what();
  }
  INFO(message);
  REQUIRE_FALSE(message.empty());
  // Stable until the bodies touched, then stopped within a few steps.
  REQUIRE(first_contact > 0);
  CHECK(sim.step() - first_contact < 20);
  CHECK(message.find("3 x the stable-step estimate") != std::string::npos);
}
