// The number of steps a run plans is counted without overflow: time.end over dt beyond what a
// run may plan (TimeSettings::kMaxSteps) is refused, naming the file, line and key, exit 2, and
// nothing is run (time.end: 1e30 wrapped the count and took one step of the whole duration,
// exit 0, "completed").
#include <catch2/catch.hpp>

#include "ball_fixture.hpp"
#include "run_helpers.hpp"

using namespace ckpd::testing;

namespace {

CommandResult run_with_time(const std::string& time) {
  const auto dir = fresh_dir("step-count");
  const std::string file =
      write_file(dir / "case.yaml",
                 steel_ball_case(
                     "conditions:\n  - {type: initial_velocity, body: ball, value: [0, 0, -10]}\n" +
                     time + "\n"));
  const CommandResult r =
      run_ckpd("run " + file + " --quiet --threads 1 --out " + (dir / "out").string());
  CHECK_FALSE(std::filesystem::exists(dir / "out" / "summary.json"));
  return r;
}

}  // namespace

TEST_CASE("an end time of more steps than a run plans is refused with its line", "[time]") {
  const CommandResult r = run_with_time("time: {end: 1.0e30}");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Catch::Contains("case.yaml:9: time.end = 1e+30 s") &&
                           Catch::Contains("(the stable step)") &&
                           Catch::Contains("more than the 1e+12 a run may plan"));
}

TEST_CASE("a time step too small for the end time is refused, naming both", "[time]") {
  const CommandResult r = run_with_time("time: {end: 1.0e-6, dt: 1.0e-300}");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Catch::Contains("case.yaml:9: time.end = 1e-06 s") &&
                           Catch::Contains("at dt = 1e-300 s (time.dt) are 1e+294 steps") &&
                           Catch::Contains("or a larger time.dt"));
}

TEST_CASE("a number of steps beyond what a run plans is refused", "[time]") {
  const CommandResult r = run_with_time("time: {steps: 2.0e12}");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Catch::Contains("case.yaml:9: time.steps") &&
                           Catch::Contains("a number of steps from 0 to 1000000000000"));
}
