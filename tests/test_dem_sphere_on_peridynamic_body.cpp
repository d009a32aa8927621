// A DEM sphere striking a free peridynamic plate obliquely, with friction: it touches the
// plate's points at R plus half the plate's own contact radius (0.375 dx by default), the pair
// exchanges equal and opposite forces at the contact points, the sphere's spin takes the
// friction couple and the plate's points' clusters take theirs (contact/point_cluster.hpp), so
// the pair's linear and angular momentum hold to rounding while the plate is pushed and the
// sphere set spinning. The plate has bonds only (nu = 1/4), so its own forces are central.
#include <catch2/catch.hpp>
#include <cmath>

#include "dem_sphere_fixtures.hpp"
#include "scene_momentum.hpp"
#include "src/case/case_loader.hpp"

using namespace ckpd;
using namespace ckpd::testing;

TEST_CASE(
    "a DEM sphere on a free peridynamic plate: the pair's momentum holds, the plate is "
    "pushed and the sphere spun",
    "[dem][dem_sphere]") {
  const double radius = 0.002, dx = 0.001;
  const auto dir = fresh_dir("dem-plate");
  std::string text =
      "materials:\n"
      "  glass: {density: 2500, youngs_modulus: 70e9, poisson_ratio: 0.25, fracture_energy: 1e6}\n"
      "bodies:\n"
      "  - {name: plate, material: glass, geometry: {type: box, min: [-0.006, -0.006, -0.003], "
      "max: [0.006, 0.006, 0]}, spacing: 0.001, horizon_ratio: 3.015}\n";
  // The plate's top points lie at z = -dx/2; the sphere starts just out of reach of them.
  const double reach = radius + 0.375 * dx;
  text += dem_sphere_entry("ball", Vec3(0.0003, 0.0002, -0.5 * dx + reach + 2e-6), radius,
                           Vec3(1.5, 0, -2), Vec3::Zero(), 7800);
  text += hertz_mindlin_contact(0.5, 0.3);
  text += "time: {end: 1e-4}\n";
  Scene scene = load_scene(write_file(dir / "case.yaml", text));
  Simulation sim(scene);
  const SceneMomentum start = scene_momentum(scene);
  double worst_p = 0, worst_l = 0;
  bool met = false;
  while (sim.step() < sim.planned_steps()) {
    sim.advance(false);
    const SceneMomentum now = scene_momentum(scene);
    worst_p = std::max(worst_p, (now.linear - start.linear).norm() / start.linear_scale);
    worst_l = std::max(worst_l, (now.angular - start.angular).norm() / start.angular_scale);
    const bool touching = sim.contact()->statistics().points_in_contact > 0;
    if (met && !touching) break;
    met = met || touching;
  }
  REQUIRE(met);
  const RigidMotion& ball = *scene.bodies[1].rigid;
  Vec3 plate = Vec3::Zero();
  const Body& b = scene.bodies[0].body;
  for (std::size_t i = 0; i < b.size(); ++i) plate += b.density * b.volume[i] * b.velocity[i];
  INFO("momentum drift " << worst_p << ", angular momentum drift " << worst_l << "; ball v "
                         << ball.velocity().transpose() << ", omega "
                         << ball.angular_velocity().transpose() << "; plate momentum "
                         << plate.transpose());
  CHECK(worst_p < 1e-12);
  CHECK(worst_l < 1e-12);
  CHECK(ball.velocity().z() > 0);             // it bounced
  CHECK(plate.z() < -0.5 * ball.mass() * 2);  // and pushed the plate down
  CHECK(ball.angular_velocity().y() > 10);    // friction turned it about +y
  CHECK(ball.velocity().x() < 1.5);           // and slowed its sliding
}
