// Friction between deformable points (docs/CONTACT_LAWS.md, "What a DEM law sees"): points carry
// no spin, so the tangential pair force acts along a line that does not join the two points and
// the pair exerts a torque (x^i - x^j) x F_t on the system. Two free 2D blocks graze each other;
// bonds only (nu = 1/3 in plane stress gives C2 = 0, and on a lattice every dV1 is equal), so the
// internal and normal contact forces are central: without friction the angular momentum is
// conserved to rounding, with friction linear momentum still is and angular momentum is not. The
// size of the change is printed (`-s`) and recorded in docs/CONTACT_LAWS.md.
#include <catch2/catch.hpp>
#include <cmath>
#include <iostream>

#include "run_helpers.hpp"
#include "src/case/case_loader.hpp"
#include "src/engine/simulation.hpp"

using namespace ckpd;
using namespace ckpd::testing;

namespace {

std::string grazing_case(double mu) {
  return R"(# SI units
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.3333333333333333}
bodies:
  - {name: low, material: steel, dimension: 2, geometry: {type: box, min: [0, 0], max: [0.008, 0.003]},
     spacing: 0.001, horizon_ratio: 3.015}
  - {name: high, material: steel, dimension: 2,
     geometry: {type: box, min: [0.002, 0.0028], max: [0.010, 0.0058]}, spacing: 0.001,
     horizon_ratio: 3.015}
conditions:
  - {type: initial_velocity, body: high, value: [20, -10]}
contact:
  stiffness: 1.0e10
  law: linear_dashpot
  restitution: 0.5
  friction: )" +
         std::to_string(mu) +
         R"(
time: {steps: 200}
)";
}

struct Momenta {
  Vec3 p = Vec3::Zero();
  double l = 0;      // z component about the origin
  double scale = 0;  // sum of m |x| |v|: the size angular momentum is measured against
};

Momenta momenta(const Scene& scene) {
  Momenta m;
  for (const SceneBody& sb : scene.bodies) {
    const Body& b = sb.body;
    for (std::size_t i = 0; i < b.size(); ++i) {
      const double mass = b.density * b.volume[i];
      const Vec3 x = b.current_position(i);
      m.p += mass * b.velocity[i];
      m.l += mass * x.cross(b.velocity[i]).z();
      m.scale += mass * x.norm() * b.velocity[i].norm();
    }
  }
  return m;
}

struct Graze {
  double momentum_change = 0, angular_change = 0, friction_work = 0;
  std::size_t contact_steps = 0;
};

Graze graze(double mu) {
  const auto dir = fresh_dir("graze");
  Scene scene = load_scene(write_file(dir / "case.yaml", grazing_case(mu)));
  Simulation sim(scene);
  const Momenta before = momenta(scene);
  Graze g;
  for (int k = 0; k < 200; ++k) {
    sim.advance(k == 199);
    g.contact_steps += sim.contact()->statistics().points_in_contact > 0;
  }
  const Momenta after = momenta(scene);
  g.momentum_change = (after.p - before.p).norm() / before.p.norm();
  g.angular_change = std::abs(after.l - before.l) / before.scale;
  g.friction_work = sim.energies().contact_friction;
  return g;
}

}  // namespace

TEST_CASE("friction between deformable points keeps linear but not angular momentum",
          "[contact][dem][friction]") {
  const Graze frictionless = graze(0.0);
  const Graze rough = graze(0.5);
  std::cout << "grazing blocks: contact for " << rough.contact_steps
            << " steps; relative change of linear momentum " << frictionless.momentum_change
            << " (mu = 0), " << rough.momentum_change << " (mu = 0.5); of angular momentum "
            << frictionless.angular_change << " (mu = 0), " << rough.angular_change
            << " (mu = 0.5); friction work " << rough.friction_work << " J/m\n";
  REQUIRE(rough.contact_steps > 10);
  REQUIRE(rough.friction_work > 0);
  CHECK(frictionless.momentum_change < 1e-12);
  CHECK(rough.momentum_change < 1e-12);
  CHECK(frictionless.angular_change < 1e-12);
  // The limitation, measured: points without spin cannot take the tangential force's couple.
  CHECK(rough.angular_change > 1e-9);
}
