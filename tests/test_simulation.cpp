// Time integration against physics the code does not define: wave speeds from the patch-test
// moduli, energy conservation, and the stable-step estimate against actual (in)stability.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "bodies/material.hpp"
#include "bodies/patch_test.hpp"
#include "reference/internal_force.hpp"
#include "run_helpers.hpp"
#include "src/case/case_loader.hpp"
#include "src/engine/simulation.hpp"

using namespace ckpd;
using namespace ckpd::testing;

namespace {

Scene scene_from_text(const std::string& tag, const std::string& text) {
  const auto dir = fresh_dir(tag);
  return load_scene(write_file(dir / "case.yaml", text));
}

// A free 3D cube, 6 x 6 x 6 points, m = 2.015, nu = 0.3 (bonds and tetrahedra), no damage.
const char* kCube = R"(
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.3}
bodies:
  - {name: cube, material: steel, geometry: {type: box, min: [0, 0, 0], max: [0.006, 0.006, 0.006]},
     spacing: 0.001, horizon_ratio: 2.015}
time: {steps: 1}
)";

// A smooth deformation mode, plus (with `noise` > 0) random velocities that excite the highest
// frequencies the lattice carries.
void excite(Body& b, double amplitude, double noise, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> random(-1, 1);
  for (std::size_t i = 0; i < b.size(); ++i) {
    const Vec3 X = b.reference_position[i] / 0.006;
    b.velocity[i] = amplitude * Vec3(std::sin(3 * X.y()), X.x() - 0.5, std::cos(2 * X.z())) +
                    noise * amplitude * Vec3(random(rng), random(rng), random(rng));
  }
}

double total_energy(const Simulation& sim) {
  const Energies e = sim.energies();
  return e.kinetic + e.strain;
}

}  // namespace

TEST_CASE("a P-wave in a laterally confined bar travels at the speed of its effective modulus",
          "[physics]") {
  // 100 x 8 x 8 points, rollers on the four long faces: a long wave is in uniaxial strain, so it
  // travels at sqrt(M_bar / rho), where M_bar = 2 w / eps^2 is the bar's own effective modulus:
  // w the strain-energy density of its middle section under the static field u = (eps x, 0, 0).
  // (The interior patch-test modulus is stiffer: the surface layers have fewer interactions.)
  const double E = 200e9, nu = 0.3, rho = 7850, m = 2.015, dx = 0.001;
  Scene scene = scene_from_text("wave", R"(
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.3}
bodies:
  - {name: bar, material: steel, geometry: {type: box, min: [0, 0, 0], max: [0.1, 0.008, 0.008]},
     spacing: 0.001, horizon_ratio: 2.015}
conditions:
  - {type: fixed, body: bar, components: [y], region: {type: box, min: [-1, -1, -1], max: [1, 0.001, 1]}}
  - {type: fixed, body: bar, components: [y], region: {type: box, min: [-1, 0.007, -1], max: [1, 1, 1]}}
  - {type: fixed, body: bar, components: [z], region: {type: box, min: [-1, -1, -1], max: [1, 1, 0.001]}}
  - {type: fixed, body: bar, components: [z], region: {type: box, min: [-1, -1, 0.007], max: [1, 1, 1]}}
time: {end: 13.0e-6}
)");
  Body& bar = scene.bodies[0].body;
  double middle_energy = 0, middle_volume = 0;
  {
    Body strained = bar;
    const double eps = 1e-6;
    for (std::size_t i = 0; i < strained.size(); ++i)
      strained.displacement[i] = Vec3(eps * strained.reference_position[i].x(), 0, 0);
    compute_internal_force(strained, true);
    for (std::size_t i = 0; i < strained.size(); ++i) {
      const double x = strained.reference_position[i].x();
      if (x > 0.04 && x < 0.06) {
        middle_energy += strained.strain_energy_density[i] * strained.volume[i];
        middle_volume += strained.volume[i];
      }
    }
    middle_energy /= middle_volume * eps * eps / 2;  // now M_bar
  }
  const double c_bar = std::sqrt(middle_energy / rho);
  const double x0 = 0.02, width = 8 * dx;
  for (std::size_t i = 0; i < bar.size(); ++i) {
    const double s = (bar.reference_position[i].x() - x0) / width;
    bar.velocity[i] = Vec3(0.1 * std::exp(-s * s), 0, 0);
  }
  Simulation sim(scene);

  const ElasticModuli moduli = elastic_moduli(3, E, nu, PlaneMode::none);
  const PatchTestResult patch = run_patch_test(3, m, E, nu, PlaneMode::none);
  const double c_eff = std::sqrt(patch.uniaxial * (moduli.lambda + 2 * moduli.mu) / rho);

  // Mean x-velocity of the 4 x 4 core points of the section at each station, over time.
  const double stations[2] = {0.04, 0.08};
  const double windows[2] = {7e-6, 13e-6};  // before the pulse reflected at x = 0 arrives
  std::vector<std::vector<std::uint32_t>> core(2);
  for (std::size_t i = 0; i < bar.size(); ++i) {
    const Vec3 X = bar.reference_position[i];
    for (int s = 0; s < 2; ++s)
      if (std::abs(X.x() - (stations[s] + dx / 2)) < 1e-9 && X.y() > 0.0019 && X.y() < 0.0061 &&
          X.z() > 0.0019 && X.z() < 0.0061)
        core[s].push_back(static_cast<std::uint32_t>(i));
  }
  REQUIRE(core[0].size() == 16);
  REQUIRE(core[1].size() == 16);
  std::vector<double> times;
  std::vector<double> signal[2];
  while (sim.step() < sim.planned_steps()) {
    sim.advance(false);
    times.push_back(sim.time());
    for (int s = 0; s < 2; ++s) {
      double v = 0;
      for (auto i : core[s]) v += scene.bodies[0].body.velocity[i].x();
      signal[s].push_back(v / 16);
    }
  }
  double arrival[2];
  for (int s = 0; s < 2; ++s) {
    std::size_t best = 0;
    for (std::size_t k = 0; k < times.size() && times[k] < windows[s]; ++k)
      if (signal[s][k] > signal[s][best]) best = k;
    REQUIRE(best > 0);
    REQUIRE(best + 1 < times.size());
    // Parabola through the three samples around the peak.
    const double a = signal[s][best - 1], b = signal[s][best], c = signal[s][best + 1];
    arrival[s] = times[best] + 0.5 * (a - c) / (a - 2 * b + c) * (times[best + 1] - times[best]);
  }
  const double c_measured = (stations[1] - stations[0]) / (arrival[1] - arrival[0]);
  INFO("measured " << c_measured << " m/s, bar modulus speed " << c_bar
                   << " m/s, interior patch-test speed " << c_eff << " m/s");
  CHECK(c_measured == Approx(c_bar).epsilon(0.03));
  CHECK(c_bar < c_eff);
}

TEST_CASE("total energy of a free elastic body drifts under 1 % over 3000 steps", "[physics]") {
  // Velocity Verlet conserves a nearby "shadow" energy: the true energy oscillates by about
  // (omega dt)^2 / 8 of the excited modes but must not drift. Drift is measured between the
  // means of the first and last 300 steps; the oscillation is bounded separately.
  Scene scene = scene_from_text("energy", kCube);
  excite(scene.bodies[0].body, 1.0, 0.0, 7);
  Simulation sim(scene);
  const double e0 = total_energy(sim);
  REQUIRE(e0 > 0);
  double worst = 0, first_mean = 0, last_mean = 0;
  for (int step = 1; step <= 3000; ++step) {
    sim.advance(true);
    const double e = total_energy(sim);
    worst = std::max(worst, std::abs(e - e0) / e0);
    if (step <= 300) first_mean += e / 300;
    if (step > 2700) last_mean += e / 300;
  }
  const double drift = std::abs(last_mean - first_mean) / e0;
  INFO("drift " << drift << ", worst oscillation " << worst);
  CHECK(drift < 0.01);
  CHECK(worst < 0.03);
}

TEST_CASE("a run at the estimated stable step stays bounded", "[physics]") {
  Scene scene = scene_from_text("stable", kCube);
  scene.time.safety = 1.0;
  excite(scene.bodies[0].body, 1.0, 0.2, 11);
  Simulation sim(scene);
  REQUIRE(sim.step_choice().dt == Approx(sim.step_choice().estimate));
  const double e0 = total_energy(sim);
  for (int step = 1; step <= 1000; ++step) REQUIRE_NOTHROW(sim.advance(step % 50 == 0));
  CHECK(std::abs(total_energy(sim) - e0) / e0 < 0.05);
}

TEST_CASE("at three times the estimated step the guard stops the run and says where", "[physics]") {
  Scene probe = scene_from_text("probe", kCube);
  const double estimate = choose_time_step(probe).estimate;
  Scene scene = scene_from_text("unstable", kCube);
  scene.time.dt = 3 * estimate;
  scene.time.allow_unstable_dt = true;
  excite(scene.bodies[0].body, 1.0, 0.2, 13);
  Simulation sim(scene);
  std::string message;
  try {
    for (int step = 1; step <= 2000; ++step) sim.advance(step % 10 == 0);
  } catch (const InstabilityError& e) {
    message = e.what();
  }
  INFO(message);
  REQUIRE_FALSE(message.empty());
  CHECK(sim.step() < 200);
  CHECK(message.find("instability at step " + std::to_string(sim.step())) != std::string::npos);
  CHECK(message.find("t = ") != std::string::npos);
  CHECK(message.find("body 'cube', point ") != std::string::npos);
  CHECK(message.find("3 x the stable-step estimate") != std::string::npos);
}

TEST_CASE("an unstable run exits non-zero and leaves a readable history and summary", "[cli]") {
  const auto dir = fresh_dir("unstable-cli");
  Scene probe = scene_from_text("probe2", kCube);
  const double estimate = choose_time_step(probe).estimate;
  std::string text = kCube;
  text +=
      "conditions:\n  - {type: initial_velocity, body: cube, value: [1, 0, 0], "
      "angular_velocity: [0, 0, 300], center: [0.003, 0.003, 0.003]}\n";
  std::ostringstream time;
  time.precision(17);
  time << "time: {steps: 2000, dt: " << 3 * estimate
       << ", allow_unstable_dt: true}\noutput: {history_interval: 5}";
  text.replace(text.find("time: {steps: 1}"), 16, time.str());
  const std::string file = write_file(dir / "case.yaml", text);
  const CommandResult r = run_ckpd("run " + file + " --quiet --out " + (dir / "out").string());
  INFO(r.output);
  CHECK(r.exit_code == 3);
  CHECK(r.output.find("instability at step") != std::string::npos);
  const auto summary = read_json(dir / "out" / "summary.json");
  CHECK(summary["status"] == "unstable");
  CHECK(summary["message"].get<std::string>().find("point") != std::string::npos);
  // Every history row is complete: the header's column count, numbers only.
  std::ifstream history(dir / "out" / "history.csv");
  std::string header, line;
  std::getline(history, header);
  const auto columns = std::count(header.begin(), header.end(), ',');
  int rows = 0;
  while (std::getline(history, line)) {
    CHECK(std::count(line.begin(), line.end(), ',') == columns);
    ++rows;
  }
  CHECK(rows >= 2);
}
