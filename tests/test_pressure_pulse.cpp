// The pressure pulse p(t) = 4 p0 u (1 - u), u = t / t1, sampled at t = k dt. A pulse of 1e-300 s
// made p0 / t1^2 infinite and the run stop as unstable with null energies; computed as
// 4 p0 u (1 - u) it is finite, but a pulse no longer than one step is zero at every sampled time
// and ran as if it had loaded the body. Such a pulse is refused with its line and key; one of a
// few steps runs with a warning that says how coarsely its impulse is sampled.
#include <catch2/catch.hpp>
#include <cmath>

#include "ball_fixture.hpp"
#include "run_helpers.hpp"

using namespace ckpd::testing;

namespace {

// The ball under a pulse of `duration` s with dt = 1e-8 s, 5 steps.
std::string pulse_case(const std::string& duration) {
  return steel_ball_case(
      "conditions:\n  - {type: pressure_pulse, body: ball, region: {type: half_space, "
      "point: [0, 0, 0.001], normal: [0, 0, 1]}, peak: 1.0e5,\n     duration: " +
      duration +
      ", direction: [0, 0, -1]}\ntime: {steps: 5, dt: 1.0e-8}\noutput: {history_interval: 1}\n");
}

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST_CASE("a pressure pulse no longer than one step is refused with its line and key",
          "[conditions]") {
  for (const char* duration : {"1.0e-300", "1.0e-8"}) {
    const auto dir = fresh_dir("pulse_short");
    const std::string file = write_file(dir / "case.yaml", pulse_case(duration));
    const CommandResult r =
        run_ckpd("run " + file + " --quiet --threads 1 --out " + (dir / "out").string());
    INFO(duration << "\n" << r.output);
    CHECK(r.exit_code == 2);
    CHECK(has(r.output, "case.yaml:9: conditions[0].duration"));
    CHECK(has(r.output, "is not longer than the time step dt = 1e-08 s"));
    CHECK_FALSE(std::filesystem::exists(dir / "out" / "summary.json"));
  }
}

TEST_CASE("a pressure pulse of a few steps runs, with a warning on its sampling",
          "[conditions][warnings]") {
  const auto dir = fresh_dir("pulse_coarse");
  const std::string file = write_file(dir / "case.yaml", pulse_case("4.0e-8"));
  const CommandResult r = run_ckpd("run " + file + " --threads 1 --out " + (dir / "out").string());
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(has(r.output,
            "case.yaml:9: conditions[0].duration: 4e-08 s on body 'ball' lasts 4 time steps"));
  const auto summary = read_json(dir / "out" / "summary.json");
  CHECK(summary["status"] == "completed");
  for (const char* key : {"kinetic", "strain", "external_work"}) {
    INFO(key << ": " << summary["energy"][key].dump());
    REQUIRE(summary["energy"][key].is_number());
  }
  // The pulse pushed: it did work on the ball.
  CHECK(summary["energy"]["external_work"].get<double>() > 0);
}

TEST_CASE("a pressure pulse of many steps runs without a warning", "[conditions][warnings]") {
  const auto dir = fresh_dir("pulse_fine");
  const std::string file = write_file(dir / "case.yaml", pulse_case("1.0e-4"));
  const CommandResult r = run_ckpd("run " + file + " --threads 1 --out " + (dir / "out").string());
  INFO(r.output);
  CHECK(r.exit_code == 0);
  // (The steel's nu = 0.3 draws its own warning, on the three-neighbour cost.)
  CHECK_FALSE(has(r.output, "time steps (dt ="));
  CHECK_FALSE(has(r.output, "conditions[0].duration"));
}
