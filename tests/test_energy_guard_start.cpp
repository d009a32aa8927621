// The energy guard at the first steps of a load that ramps up from zero: by the first step's
// drift the load has done no work (the points were at rest when it was zero), yet the step's
// last kick gave them kinetic energy. The guard's reference counts the loads' work over that
// kick, so a harmless first step is not stopped as unstable ("more than ten times the energy
// put in (0 J)").
#include <catch2/catch.hpp>

#include "run_helpers.hpp"

using namespace ckpd::testing;

TEST_CASE("a pressure ramp from zero passes the energy guard at step 1", "[energy]") {
  const auto dir = fresh_dir("guard-start");
  const std::string file = std::string(CKPD_SOURCE_DIR) + "/tests/data/inputs/pulse_one_step.yaml";
  const CommandResult r =
      run_ckpd("run " + file + " --quiet --threads 1 --out " + (dir / "out").string());
  INFO(r.output);
  CHECK(r.exit_code == 0);
  const auto summary = read_json(dir / "out" / "summary.json");
  CHECK(summary["status"] == "completed");
  CHECK(summary["steps"] == 1);
}

TEST_CASE("the curved bar's first step with energy passes the guard", "[energy]") {
  // `ckpd check` evaluates the energy at every step it takes.
  const std::string file = std::string(CKPD_SOURCE_DIR) + "/cases/curved_bar_2d.yaml";
  const CommandResult r = run_ckpd("check " + file + " --steps 1 --threads 2");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("instability") == std::string::npos);
}
