// A run to time.end ends exactly there: the last step is shortened to the remainder (never
// past it), every earlier step is dt, and a restart to a later end continues from the
// checkpoint's time with the same dt.
#include <catch2/catch.hpp>
#include <fstream>
#include <sstream>
#include <vector>

#include "run_helpers.hpp"
#include "src/case/case_loader.hpp"
#include "src/engine/simulation.hpp"

using namespace ckpd;
using namespace ckpd::testing;

namespace {

// dt is given so the remainder is known: 1.5e-6 / 0.4e-7 = 37.5 steps.
const char* kCase = R"(# SI units
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.25}
bodies:
  - {name: strip, material: steel, dimension: 2, geometry: {type: box, min: [0, 0], max: [0.02, 0.004]},
     spacing: 0.001, horizon_ratio: 3.015}
conditions:
  - {type: initial_velocity, body: strip, value: [1, 0]}
time: {end: 1.5e-6, dt: 0.4e-7}
output: {history_interval: 5}
)";

std::vector<double> history_times(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::vector<double> t;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string step, time;
    std::getline(row, step, ',');
    std::getline(row, time, ',');
    t.push_back(std::stod(time));
  }
  return t;
}

}  // namespace

TEST_CASE("the last step lands exactly on time.end", "[cli][end_time]") {
  const auto dir = fresh_dir("end-time");
  Scene scene = load_scene(write_file(dir / "case.yaml", kCase));
  Simulation sim(scene);
  CHECK(sim.planned_steps() == 38);
  CHECK(sim.step_size(1) == 0.4e-7);
  CHECK(sim.step_size(37) == 0.4e-7);
  CHECK(sim.step_size(38) == Approx(0.2e-7).epsilon(1e-9));
  while (sim.step() < sim.planned_steps()) {
    sim.advance(false);
    CHECK(sim.time() <= 1.5e-6);
  }
  CHECK(sim.time() == 1.5e-6);
  // The strip moves at 1 m/s: its displacement is the time it ran, to rounding.
  CHECK(scene.bodies[0].body.displacement[0].x() == Approx(1.5e-6).epsilon(1e-9));

  // Through the program: summary and the history's last row say the same.
  const CommandResult r =
      run_ckpd("run " + (dir / "case.yaml").string() + " --quiet --out " + (dir / "out").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto summary = read_json(dir / "out" / "summary.json");
  CHECK(summary["time"] == 1.5e-6);
  CHECK(summary["steps"] == 38);
  CHECK(history_times(dir / "out" / "history.csv").back() == 1.5e-6);
}

TEST_CASE("a restart to a later time.end continues from the checkpoint's time", "[cli][end_time]") {
  const auto dir = fresh_dir("end-time-restart");
  const std::string file = write_file(dir / "case.yaml", kCase);
  const auto out = (dir / "out").string();
  REQUIRE(run_ckpd("run " + file + " --quiet --out " + out + " --set output.checkpoint_interval=38")
              .exit_code == 0);
  const CommandResult r = run_ckpd("run " + file + " --quiet --out " + out +
                                   " --set time.end=3e-6 --restart " + out + "/checkpoint.h5");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto summary = read_json(dir / "out" / "summary.json");
  CHECK(summary["time"] == 3e-6);
  // 1.5e-6 s more at 0.4e-7 s: 37.5 steps again.
  CHECK(summary["steps"] == 76);
  const std::vector<double> t = history_times(dir / "out" / "history.csv");
  for (std::size_t k = 1; k < t.size(); ++k) CHECK(t[k] >= t[k - 1]);
  CHECK(t.back() == 3e-6);
}
