// A run stopped at a step between history rows (a signal, an instability) writes a last row and
// a summary whose strain energy is that of the step it stopped at, not of the row before; the
// extra evaluation leaves the step's forces alone, so the run continued from there is the same
// bit for bit.
#include <catch2/catch.hpp>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "run_helpers.hpp"
#include "src/case/case_loader.hpp"
#include "src/engine/simulation.hpp"
#include "src/output/run_driver.hpp"

using namespace ckpd::testing;

namespace {

// A pre-cracked 2D strip pulled apart: bonds break and the strain energy changes every step.
const char* kCase = R"(# SI units
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.3, fracture_energy: 50}
bodies:
  - name: strip
    material: steel
    dimension: 2
    geometry: {type: box, min: [0, 0], max: [0.03, 0.015]}
    spacing: 0.001
    horizon_ratio: 3.015
    precracks: [[[0, 0.0075], [0.01, 0.0075]]]
conditions:
  - {type: velocity, body: strip, region: {type: box, min: [0, 0.0135], max: [0.03, 0.015]}, value: [0, 3], components: [y]}
  - {type: velocity, body: strip, region: {type: box, min: [0, 0], max: [0.03, 0.0015]}, value: [0, -3], components: [y]}
time: {steps: 200}
output: {history_interval: 10}
)";

// The strain energy column of history.csv's last row.
double last_row_strain(const std::filesystem::path& history) {
  std::ifstream in(history);
  std::string header, line, last;
  std::getline(in, header);
  std::size_t column = 0;
  {
    std::stringstream h(header);
    std::string name;
    for (std::size_t k = 0; std::getline(h, name, ','); ++k)
      if (name == "strain") column = k;
  }
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  std::stringstream r(last);
  std::string cell;
  for (std::size_t k = 0; k <= column; ++k) std::getline(r, cell, ',');
  return std::stod(cell);
}

}  // namespace

TEST_CASE("a run stopped between history rows reports the strain energy of its last step",
          "[output]") {
  const auto dir = fresh_dir("stop_between_rows");
  const std::string file = write_file(dir / "case.yaml", kCase);
  constexpr int kStopped = 45;  // between the rows at 40 and 50

  // Stopped by the driver at step 45, as on SIGTERM.
  ckpd::Scene scene = ckpd::load_scene(file, {});
  ckpd::Simulation sim(scene);
  ckpd::RunDriverOptions options;
  options.out = (dir / "out").string();
  ckpd::RunDriver driver(sim, options);
  double row_before = 0;
  for (int s = 1; s <= kStopped; ++s) {
    driver.step();
    if (s == 40) row_before = sim.energies().strain;
  }
  driver.stop("interrupted", "test");

  // The same run with an evaluation with energy at step 45 (and at the rows, as the driver's).
  ckpd::Scene scene_b = ckpd::load_scene(file, {});
  ckpd::Simulation sim_b(scene_b);
  for (int s = 1; s <= kStopped; ++s) sim_b.advance(s % 10 == 0 || s == kStopped);
  const double expected = sim_b.energies().strain;
  REQUIRE(sim_b.broken_bonds() > 0);
  // The stale value would be visibly wrong: five steps of a tear change the strain energy.
  REQUIRE(std::abs(expected - row_before) > 1e-3 * std::abs(expected));

  const auto summary = read_json(dir / "out" / "summary.json");
  CHECK(summary["steps"] == kStopped);
  CHECK(double(summary["energy"]["strain"]) == Approx(expected).epsilon(1e-13));
  // history.csv holds 10 significant digits.
  CHECK(last_row_strain(dir / "out" / "history.csv") == Approx(expected).epsilon(1e-9));

  // Continued after the stop, the run is the one that never stopped.
  for (int s = 0; s < 20; ++s) {
    sim.advance(false);
    sim_b.advance(false);
  }
  const auto& a = scene.bodies[0].body.displacement;
  const auto& b = scene_b.bodies[0].body.displacement;
  REQUIRE(a.size() == b.size());
  CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof a[0]) == 0);
  CHECK(sim.broken_bonds() == sim_b.broken_bonds());
}
