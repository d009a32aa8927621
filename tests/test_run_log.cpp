// DIR/run.log holds the set-up lines, progress lines and the final line, time-stamped, and
// summary.json records how the run was made (command line, overrides, version, build flags).
#include <catch2/catch.hpp>
#include <fstream>
#include <sstream>

#include "run_helpers.hpp"
#include "src/output/progress.hpp"

using namespace ckpd;
using namespace ckpd::testing;

namespace {

const char* kCase = R"(# SI units
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.25}
bodies:
  - {name: strip, material: steel, dimension: 2, geometry: {type: box, min: [0, 0], max: [0.01, 0.004]},
     spacing: 0.001, horizon_ratio: 3.015}
time: {steps: 10}
)";

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST_CASE("a run writes run.log and records its provenance in summary.json", "[cli][log]") {
  const auto dir = fresh_dir("run-log");
  const std::string file = write_file(dir / "case.yaml", kCase);
  const auto out = dir / "out";
  const CommandResult r = run_ckpd("run " + file + " --quiet --threads 1 --out " + out.string() +
                                   " --set time.steps=12");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.empty());  // --quiet: the log is the file's, not the terminal's
  const std::string log = slurp(out / "run.log");
  INFO(log);
  CHECK(log.find("ckpd 0.") != std::string::npos);
  CHECK(log.find("command: ") != std::string::npos);
  CHECK(log.find("override: --set time.steps=12") != std::string::npos);
  CHECK(log.find("body 'strip': 2D, 40 points") != std::string::npos);
  CHECK(log.find("time step: estimate") != std::string::npos);
  CHECK(log.find("step 12/12") != std::string::npos);  // the last progress line
  CHECK(log.find("completed 12 steps") != std::string::npos);
  // Every line starts with its UTC time.
  std::istringstream lines(log);
  for (std::string line; std::getline(lines, line);) {
    REQUIRE(line.size() > 22);
    CHECK(line[4] == '-');
    CHECK(line[10] == 'T');
    CHECK(line[19] == 'Z');
  }
  const auto summary = read_json(out / "summary.json");
  const auto& p = summary["provenance"];
  CHECK(p["overrides"] == std::vector<std::string>{"time.steps=12"});
  const std::string command = p["command_line"];
  CHECK(command.find(" run ") != std::string::npos);
  CHECK(command.find("--set time.steps=12") != std::string::npos);
  CHECK(p["build"]["version"].get<std::string>().rfind("0.", 0) == 0);
  CHECK(!p["build"]["flags"].get<std::string>().empty());
  CHECK(!p["build"]["build_type"].get<std::string>().empty());
  CHECK(!p["build"]["arch"].get<std::string>().empty());
  CHECK(p["build"]["isa_extensions"].is_array());
}

TEST_CASE("the progress line fits the width it is given and labels its figures", "[cli][log]") {
  ProgressState s;
  s.step = 123456;
  s.total = 1000000;
  s.time = 1.234567e-5;
  s.elapsed = 3725;
  s.rate = 33.3;
  s.max_damage = 0.4567;
  s.energy_step = 123400;
  s.energy_error = 0.043;
  const std::string wide = format_progress(s, 1000);
  INFO(wide);
  for (const char* part :
       {" 12.3%", "step 123456/1000000", "t 1.235e-05 s", "elapsed 1:02:05",
        "ETA 7:18:", "33.3 steps/s", "damage 0.457", "energy error 4.3% (at step 123400)"})
    CHECK(wide.find(part) != std::string::npos);
  for (std::size_t width : {20u, 40u, 79u, 100u}) {
    const std::string line = format_progress(s, width);
    INFO(line);
    CHECK(line.size() <= width);
    CHECK(line.find("12.3%") != std::string::npos);
  }
  CHECK(format_progress(s, 79).find("ETA") != std::string::npos);
  s.energy_step = -1;
  CHECK(format_progress(s, 1000).find("energy error: not yet evaluated") != std::string::npos);
  CHECK(format_duration(59.4) == "59 s");
  CHECK(format_duration(61) == "1:01");
}
