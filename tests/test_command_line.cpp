// The `ckpd` command line as a user meets it: every usage error exits 2 with one line naming
// the bad argument, --version names the build, --set errors name the override, misspelt keys
// are named with the nearest known key, and --set time.steps replaces time.end.
#include <catch2/catch.hpp>
#include <filesystem>
#include <sstream>

#include "run_helpers.hpp"
#include "src/input/nearest_name.hpp"

using namespace ckpd::testing;

namespace {

const char* kCase = R"(# a small 2D plate, SI units
materials:
  steel: {density: 7580, youngs_modulus: 210e9, poisson_ratio: 0.3}
bodies:
  - {name: plate, material: steel, dimension: 2, geometry: {type: box, min: [0, 0], max: [0.02, 0.02]},
     spacing: 0.005, horizon_ratio: 3.015}
time: {end: 1.0e-6}
)";

std::size_t lines(const std::string& text) {
  std::size_t n = 0;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) n += !line.empty();
  return n;
}

// A usage error: exit 2, one line, naming `what`.
void expect_usage_error(const std::string& args, const std::string& what) {
  const CommandResult r = run_ckpd(args);
  INFO("ckpd " << args << "\n" << r.output);
  CHECK(r.exit_code == 2);
  CHECK(lines(r.output) == 1);
  CHECK(r.output.find(what) != std::string::npos);
}

std::string case_file(const std::filesystem::path& dir, const std::string& text = kCase) {
  return write_file(dir / "case.yaml", text);
}

}  // namespace

TEST_CASE("usage errors exit 2 with one line naming the bad argument", "[cli][usage]") {
  const auto dir = fresh_dir("usage");
  const std::string file = case_file(dir);
  expect_usage_error("runn " + file, "unknown command 'runn' (did you mean 'run'?)");
  expect_usage_error("", "no command given");
  expect_usage_error("run", "case");
  expect_usage_error("run " + file + " --threds 2", "--threds");
  expect_usage_error("run " + file + " --threads 0", "from 1 to 4096, got '0'");
  expect_usage_error("run " + file + " --threads 5000", "from 1 to 4096, got '5000'");
  expect_usage_error("run " + file + " --threads two", "got 'two'");
  expect_usage_error("check " + file + " --threads 0", "from 1 to 4096");
  expect_usage_error("patch-test --dim 4", "--dim");
  expect_usage_error("run " + file + " " + file, file);
}

TEST_CASE("the help and the version exit 0; the version names the version and the build",
          "[cli][usage]") {
  CommandResult r = run_ckpd("--help");
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("run") != std::string::npos);
  r = run_ckpd("--version");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(r.output.rfind("ckpd 0.", 0) == 0);
  CHECK(r.output.find("flags") != std::string::npos);
  CHECK(r.output.find("commit") != std::string::npos);
  CHECK(r.output.find("instruction set CKPD_ARCH=") != std::string::npos);
}

TEST_CASE("an error in a --set value names the override, not a line of the case", "[cli][usage]") {
  const auto dir = fresh_dir("set-error");
  const std::string file = case_file(dir);
  const CommandResult r = run_ckpd("run " + file + " --quiet --out " + (dir / "out").string() +
                                   " --set bodies.plate.spacing=-1");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("--set bodies.plate.spacing=-1: bodies[0].spacing: expected a positive") !=
        std::string::npos);
  CHECK(r.output.find("case.yaml:") == std::string::npos);
  // A new key put in by --set that the case does not know: named as the override's.
  const CommandResult k = run_ckpd("run " + file + " --quiet --out " + (dir / "out").string() +
                                   " --set time.ends=2e-6");
  INFO(k.output);
  CHECK(k.exit_code == 2);
  CHECK(k.output.find("--set time.ends=2e-6") != std::string::npos);
  CHECK(k.output.find("did you mean 'end'") != std::string::npos);
}

TEST_CASE("a misspelt key is named with the nearest known key", "[cli][usage]") {
  const auto dir = fresh_dir("misspelt");
  auto expect = [&](const std::string& from, const std::string& to,
                    std::initializer_list<std::string> fragments) {
    std::string text = kCase;
    const auto at = text.find(from);
    REQUIRE(at != std::string::npos);
    text.replace(at, from.size(), to);
    const CommandResult r =
        run_ckpd("run " + case_file(dir, text) + " --quiet --out " + (dir / "out").string());
    INFO(r.output);
    CHECK(r.exit_code == 2);
    for (const std::string& f : fragments) CHECK(r.output.find(f) != std::string::npos);
  };
  // A required key misspelt: not "missing required key".
  expect("youngs_modulus", "young_modulus",
         {"case.yaml:3: materials.steel.young_modulus: unknown key 'young_modulus'",
          "did you mean 'youngs_modulus'?"});
  // An alternative key misspelt (horizon or horizon_ratio).
  expect("horizon_ratio", "horizon_ration",
         {"unknown key 'horizon_ration'", "did you mean 'horizon_ratio'?"});
  // One of two alternatives (end or steps).
  expect("time: {end: 1.0e-6}", "time: {ends: 1.0e-6}",
         {"unknown key 'ends'", "did you mean 'end'?"});
}

TEST_CASE("nearest_name suggests only close names", "[cli][usage]") {
  CHECK(ckpd::edit_distance("horizon_ration", "horizon_ratio") == 1);
  CHECK(ckpd::edit_distance("stpes", "steps") == 1);  // a swap counts one
  CHECK(ckpd::nearest_name("young_modulus", {"density", "youngs_modulus", "poisson_ratio"}) ==
        "youngs_modulus");
  CHECK(ckpd::nearest_name("velocity", {"density", "youngs_modulus"}).empty());
  CHECK(ckpd::nearest_name("x", {"y"}) == "y");
  CHECK(ckpd::nearest_name("ab", {"xy"}).empty());
}

TEST_CASE(
    "time.steps set on the command line replaces the case's time.end, and time.end its time.steps",
    "[cli][usage]") {
  const auto dir = fresh_dir("set-steps");
  const std::string file = case_file(dir);
  CommandResult r =
      run_ckpd("run " + file + " --quiet --out " + (dir / "a").string() + " --set time.steps=7");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(read_json(dir / "a" / "summary.json")["steps"] == 7);
  r = run_ckpd("run " + file + " --quiet --out " + (dir / "b").string() +
               " --set time.steps=7 --set time.end=2e-7");
  REQUIRE(r.exit_code == 0);
  CHECK(read_json(dir / "b" / "summary.json")["time"] == 2e-7);
}
