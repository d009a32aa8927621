// A `velocity` with a `duration` prescribes its points only until then: afterwards they move
// under their forces and the load does no more work. A duration not longer than the ramp is bad
// input, and so is one that ends before the first step does.
#include <catch2/catch.hpp>
#include <string>

#include "contact_fixtures.hpp"

using namespace ckpd;
using namespace ckpd::testing;

namespace {

std::string bar(const std::string& velocity_keys) {
  return "materials:\n  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.25}\n"
         "bodies:\n  - {name: bar, material: steel, geometry: {type: box, min: [0, 0, 0], max: "
         "[0.01, 0.002, 0.002]}, spacing: 0.001, horizon_ratio: 2.015}\n"
         "conditions:\n  - {type: velocity, body: bar, region: {type: box, min: [-1, -1, -1], "
         "max: [0.0021, 1, 1]}, value: [5, 0, 0]" +
         velocity_keys + "}\ntime: {end: 2.0e-5}\n";
}

}  // namespace

TEST_CASE("a velocity with a duration lets its points go after it", "[conditions]") {
  Scene scene = scene_from_text("duration", bar(", ramp_time: 1.0e-6, duration: 5.0e-6"));
  Simulation sim(scene);
  // The step across the release still books the reaction's work over its first half.
  double work_at_release = -1, largest_change = 0;
  bool released_free = false;
  while (sim.step() < sim.planned_steps()) {
    sim.advance(false);
    if (sim.time() <= 5.0e-6) continue;
    if (work_at_release < 0) {
      work_at_release = sim.energies().external_work;
    } else {
      // No more work is done, and the driven points no longer all move at exactly 5 m/s.
      largest_change =
          std::max(largest_change, std::abs(sim.energies().external_work - work_at_release));
      const Body& b = scene.bodies[0].body;
      for (std::uint32_t i : scene.bodies[0].conditions[0]->points())
        released_free = released_free || b.velocity[i].x() != 5.0;
    }
  }
  INFO("work at release " << work_at_release << " J, change after " << largest_change << " J");
  CHECK(work_at_release > 0);
  CHECK(largest_change <= 1e-12 * work_at_release);
  CHECK(released_free);
}

TEST_CASE("a velocity's duration must be longer than its ramp", "[conditions][hardened]") {
  const auto dir = fresh_dir("duration-bad");
  for (const std::string keys : {", ramp_time: 1.0e-6, duration: 1.0e-6", ", duration: -1"}) {
    const CommandResult r =
        run_ckpd("check " + write_file(dir / "case.yaml", bar(keys)) + " --steps 0");
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("case.yaml:6: conditions[0].duration") != std::string::npos);
    CHECK(r.output.find("duration") != std::string::npos);
  }
}

TEST_CASE("a velocity's duration no longer than one step is refused", "[conditions][hardened]") {
  // The bar's stable step is about 1e-7 s: a 1e-12 s hold ends before the first step does.
  const auto dir = fresh_dir("duration-short");
  const CommandResult r =
      run_ckpd("check " + write_file(dir / "case.yaml", bar(", duration: 1.0e-12")) + " --steps 0");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("case.yaml:6: conditions[0].duration = 1e-12 s on body 'bar' is not "
                      "longer than the time step") != std::string::npos);
}
