// Tabulated condition values (value: {table: [[t, v...], ...]}): linear between rows, held
// outside them, with the slope as the prescribed acceleration; a prescribed velocity, a
// pressure and gravity follow their tables in a run; bad tables are rejected.
#include <catch2/catch.hpp>

#include "run_helpers.hpp"
#include "src/case/case_loader.hpp"
#include "src/engine/simulation.hpp"
#include "src/engine/time_table.hpp"

using namespace ckpd;
using namespace ckpd::testing;

TEST_CASE("a time table interpolates linearly and holds its end values", "[conditions][table]") {
  const TimeTable t({0.0, 1.0, 3.0}, {Vec3(0, 0, 0), Vec3(2, -1, 0), Vec3(2, 3, 1)});
  CHECK(t.value(-1) == Vec3(0, 0, 0));
  CHECK(t.value(0.5).isApprox(Vec3(1, -0.5, 0)));
  CHECK(t.value(2.0).isApprox(Vec3(2, 1, 0.5)));
  CHECK(t.value(5.0) == Vec3(2, 3, 1));
  CHECK(t.rate(0.5).isApprox(Vec3(2, -1, 0)));
  CHECK(t.rate(2.0).isApprox(Vec3(0, 2, 0.5)));
  CHECK(t.rate(4.0) == Vec3::Zero());
  CHECK(t.max_norm() == Approx(std::sqrt(14.0)));
  CHECK(TimeTable(Vec3(1, 2, 3)).value(7) == Vec3(1, 2, 3));
}

TEST_CASE("a step time table holds each row's value until the next row's time",
          "[conditions][table]") {
  const TimeTable t({1.0, 2.0, 4.0}, {Vec3(1, 0, 0), Vec3(-2, 5, 0), Vec3(3, 3, 3)},
                    Interpolation::step);
  CHECK(t.value(0.0) == Vec3(1, 0, 0));  // before the first row: its value
  CHECK(t.value(1.0) == Vec3(1, 0, 0));
  CHECK(t.value(1.999) == Vec3(1, 0, 0));
  CHECK(t.value(2.0) == Vec3(-2, 5, 0));  // from a row's own time on
  CHECK(t.value(3.5) == Vec3(-2, 5, 0));
  CHECK(t.value(4.0) == Vec3(3, 3, 3));
  CHECK(t.value(9.0) == Vec3(3, 3, 3));
  for (double time : {0.0, 1.5, 2.0, 3.0, 5.0}) CHECK(t.rate(time) == Vec3::Zero());
}

namespace {

// A 2D strip: its left column follows a tabulated velocity; gravity and a pressure on the right
// column follow theirs. nu = 1/3 in plane stress gives C2 = 0, whose internal forces sum to
// zero exactly (the two-neighbour forces do not near surfaces), so momentum is the impulse.
std::string strip_case(const std::string& conditions) {
  return R"(# SI units
materials:
  steel: {density: 8000, youngs_modulus: 200e9, poisson_ratio: 0.3333333333333333}
bodies:
  - {name: strip, material: steel, dimension: 2, geometry: {type: box, min: [0, 0], max: [0.01, 0.004]},
     spacing: 0.001, horizon_ratio: 3.015}
conditions:
)" + conditions +
         "time: {steps: 100, dt: 1.0e-8}\n";
}

}  // namespace

TEST_CASE("a prescribed velocity follows its table: the displacement is its integral",
          "[conditions][table]") {
  const auto dir = fresh_dir("table-velocity");
  // v_x: 0 -> 2 m/s over 0.4 us, then back to 0 at 0.8 us; held at 0 afterwards.
  Scene scene = load_scene(write_file(
      dir / "case.yaml",
      strip_case("  - {type: velocity, body: strip, region: {type: box, min: [0, 0], max: [0.001, "
                 "0.004]}, value: {table: [[0, 0, 0], [0.4e-6, 2, 0], [0.8e-6, 0, 0]]}}\n")));
  Simulation sim(scene);
  const Body& b = scene.bodies[0].body;
  const std::uint32_t held = scene.bodies[0].conditions[0]->points()[0];
  while (sim.step() < 60) {
    sim.advance(false);
    const double t = sim.time();
    const double v = t <= 0.4e-6 ? 2 * t / 0.4e-6 : 2 * (0.8e-6 - t) / 0.4e-6;
    CHECK(b.velocity[held].x() == Approx(v).margin(1e-9));
  }
  // Area under the triangle up to 0.6 us: 0.4 us x 2 m/s / 2 + 0.2 us x (2 + 1) m/s / 2.
  CHECK(b.displacement[held].x() == Approx(0.4e-6 + 0.3e-6).epsilon(1e-9));
  while (sim.step() < 100) sim.advance(false);
  CHECK(b.velocity[held].x() == 0);
  CHECK(b.displacement[held].x() == Approx(0.8e-6).epsilon(1e-9));
}

TEST_CASE("gravity and a pressure follow their tables: the momentum is the impulse",
          "[conditions][table]") {
  const auto dir = fresh_dir("table-loads");
  Scene scene = load_scene(write_file(
      dir / "case.yaml",
      strip_case("  - {type: gravity, body: strip, acceleration: {table: [[0, 0, 0], [1e-6, 0, "
                 "-1000]]}}\n"
                 "  - {type: pressure, body: strip, region: {type: box, min: [0.009, 0], max: "
                 "[0.01, 0.004]}, direction: [1, 0], value: {table: [[0, 0], [0.5e-6, 1e6], "
                 "[1e-6, 1e6]]}}\n")));
  Simulation sim(scene);
  const Body& b = scene.bodies[0].body;
  while (sim.step() < 100) sim.advance(false);
  Vec3 p = Vec3::Zero();
  for (std::size_t i = 0; i < b.size(); ++i) p += b.density * b.volume[i] * b.velocity[i];
  // Gravity: m x the integral of g (a ramp to -1000 m/s^2 over 1 us: -500e-6 m/s).
  CHECK(p.y() == Approx(b.mass() * -1000 * 0.5e-6).epsilon(1e-6));
  // Pressure: 1e6 N/m over the 4 mm edge (4 points x dx^2 / dx), ramped in 0.5 us, then held.
  const double force = 1e6 * 0.004;
  CHECK(p.x() == Approx(force * (0.25e-6 + 0.5e-6)).epsilon(1e-6));
}

TEST_CASE("a bad time table is rejected with the row", "[conditions][table]") {
  const auto dir = fresh_dir("table-bad");
  auto run = [&](const std::string& value) {
    return run_ckpd(
        "run " +
        write_file(dir / "case.yaml",
                   strip_case("  - {type: velocity, body: strip, value: " + value + "}\n")) +
        " --quiet --out " + (dir / "out").string());
  };
  CommandResult r = run("{table: [[0, 0, 0], [0, 1, 0]]}");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("value.table[1]: expected a time after the previous row's") !=
        std::string::npos);
  r = run("{table: [[0, 0]]}");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("expected a row [t, vx, vy]") != std::string::npos);
  r = run("{table: [[0, 0, 0]], interpolation: cubic}");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("value.interpolation: expected linear or step") != std::string::npos);
  r = run("{tabel: [[0, 0, 0]]}");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("did you mean 'table'") != std::string::npos);
}
