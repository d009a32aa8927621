// The pressure pulse p(t) = 4 p0 u (1 - u), u = t / t1, is finite for every duration t1 > 0: a
// pulse of 1e-300 s made p0 / t1^2 infinite and the run stop as unstable with null energies.
#include <catch2/catch.hpp>
#include <cmath>

#include "ball_fixture.hpp"
#include "run_helpers.hpp"

using namespace ckpd::testing;

TEST_CASE("a pressure pulse of any positive duration gives finite energies", "[conditions]") {
  for (const char* duration : {"1.0e-300", "1.0e-4"}) {
    const auto dir = fresh_dir("pulse");
    const std::string text = steel_ball_case(
        std::string(
            "conditions:\n  - {type: pressure_pulse, body: ball, region: {type: half_space, "
            "point: [0, 0, 0.001], normal: [0, 0, 1]}, peak: 1.0e5, duration: ") +
        duration + ", direction: [0, 0, -1]}\ntime: {steps: 5}\noutput: {history_interval: 1}\n");
    const std::string file = write_file(dir / "case.yaml", text);
    const CommandResult r =
        run_ckpd("run " + file + " --quiet --threads 1 --out " + (dir / "out").string());
    INFO(duration << "\n" << r.output);
    CHECK(r.exit_code == 0);
    const auto summary = read_json(dir / "out" / "summary.json");
    CHECK(summary["status"] == "completed");
    for (const char* key : {"kinetic", "strain", "external_work"}) {
      INFO(key << ": " << summary["energy"][key].dump());
      CHECK(summary["energy"][key].is_number());
    }
  }
}
