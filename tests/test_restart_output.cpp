// What a restart does to the files of the run it continues: the history keeps only the rows the
// uninterrupted run writes (not the extra row of a run stopped off its schedule, by SIGTERM or an
// earlier end), and the XDMF indexes keep listing the kept frames from the first moment on (a
// restart that is stopped, or whose disk is full, before its next frame leaves them indexed).
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "full_disk.hpp"
#include "run_helpers.hpp"

using namespace ckpd::testing;
namespace fs = std::filesystem;

namespace {

// A 2D strip of 21 x 11 points pulled apart at its ends; a history row every 10 steps.
const char* kCase = R"(# SI units
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.2, fracture_energy: 50}
bodies:
  - {name: strip, material: steel, dimension: 2, geometry: {type: box, min: [0, 0], max: [0.02, 0.01]},
     spacing: 0.001, horizon_ratio: 3.015}
conditions:
  - {type: velocity, body: strip, region: {type: box, min: [0, 0], max: [0.002, 0.01]}, value: [-5, 0], components: [x]}
  - {type: velocity, body: strip, region: {type: box, min: [0.018, 0], max: [0.02, 0.01]}, value: [5, 0], components: [x]}
time: {steps: 60}
output: {history_interval: 10, field_interval: 20, checkpoint_interval: 20, fields: [damage]}
)";

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The time steps an XDMF index lists (one Time element each).
std::size_t frames_listed(const fs::path& xdmf) {
  const std::string text = slurp(xdmf);
  std::size_t n = 0;
  for (auto at = text.find("<Time "); at != std::string::npos; at = text.find("<Time ", at + 1))
    ++n;
  return n;
}

}  // namespace

TEST_CASE("a restart from a run stopped off the row schedule writes the uninterrupted history",
          "[restart][output]") {
  const fs::path dir = fresh_dir("history-rows");
  const std::string file = write_file(dir / "case.yaml", kCase);
  const std::string run = "run " + file + " --quiet --threads 1 --out ";
  REQUIRE(run_ckpd(run + (dir / "whole").string()).exit_code == 0);
  // Stopped at step 23 with a checkpoint there: its last row (step 23) is off the schedule, as
  // the row a run stopped by SIGTERM writes at the signal's step.
  const fs::path part = dir / "part";
  REQUIRE(run_ckpd(run + part.string() + " --set time.steps=23 --set output.checkpoint_interval=23")
              .exit_code == 0);
  CHECK(slurp(part / "history.csv").find("\n23,") != std::string::npos);
  fs::copy_file(part / "checkpoint.h5", dir / "at23.h5");
  const CommandResult r =
      run_ckpd(run + part.string() + " --restart " + (dir / "at23.h5").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(slurp(part / "history.csv") == slurp(dir / "whole" / "history.csv"));
}

TEST_CASE("SIGTERM then a restart writes the history of the uninterrupted run",
          "[restart][output]") {
  const fs::path dir = fresh_dir("sigterm-rows");
  std::string text = kCase;
  text.replace(text.find("time: {steps: 60}"), 17, "time: {steps: 100000000}");
  const std::string file = write_file(dir / "case.yaml", text);
  const fs::path out = dir / "out";
  const CommandResult stopped =
      run_ckpd("run " + file + " --quiet --threads 1 --out " + out.string() +
               " & pid=$!; sleep 2; kill -TERM $pid; wait $pid; echo exit=$?");
  INFO(stopped.output);
  REQUIRE(stopped.output.find("exit=130") != std::string::npos);
  const long long at = read_json(out / "summary.json")["steps"];
  const long long end = (at / 10 + 3) * 10;
  const std::string steps = " --set time.steps=" + std::to_string(end);
  const CommandResult more = run_ckpd("run " + file + " --quiet --threads 1 --out " + out.string() +
                                      " --restart " + (out / "checkpoint.h5").string() + steps);
  INFO(more.output);
  REQUIRE(more.exit_code == 0);
  REQUIRE(run_ckpd("run " + file + " --quiet --threads 1 --out " + (dir / "whole").string() + steps)
              .exit_code == 0);
  CHECK(slurp(out / "history.csv") == slurp(dir / "whole" / "history.csv"));
}

TEST_CASE("a restart keeps its kept frames indexed from the start", "[restart][output]") {
  const fs::path dir = fs::canonical(fresh_dir("restart-index"));
  const std::string file = write_file(dir / "case.yaml", kCase);
  const fs::path out = dir / "out";
  const std::string run = "run " + file + " --quiet --threads 1 --out " + out.string();
  // Frames at steps 0, 20, 40 and a checkpoint at 40.
  REQUIRE(run_ckpd(run + " --set time.steps=40").exit_code == 0);
  REQUIRE(frames_listed(out / "fields.xdmf") == 3);
  fs::copy_file(out / "checkpoint.h5", dir / "at40.h5");
  const std::string restart = run + " --restart " + (dir / "at40.h5").string();
  SECTION("a restart with no step left writes no frame, and the index stays") {
    const CommandResult r = run_ckpd(restart + " --set time.steps=40");
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    CHECK(frames_listed(out / "fields.xdmf") == 3);
    CHECK(frames_listed(out / "fields_strip.xdmf") == 3);
  }
  SECTION("a restart whose disk fills up before its next frame leaves the frames indexed") {
    for (long long k = 1; k <= 12; ++k) {
      const CommandResult r = run_ckpd_on_full_disk(out, k, restart);
      INFO("full from write " << k << ": " << r.output);
      CHECK(r.exit_code != 0);
      CHECK(frames_listed(out / "fields.xdmf") >= 3);
      CHECK(frames_listed(out / "fields_strip.xdmf") >= 3);
    }
  }
}
