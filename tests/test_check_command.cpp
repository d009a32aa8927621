// `ckpd check` validates without running: sizes, the limiting stable-step term, a projection.
#include <catch2/catch.hpp>
#include <filesystem>

#include "run_helpers.hpp"

using namespace ckpd::testing;

namespace {
const char* kCase = R"(# SI units
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.3}
bodies:
  - {name: cube, material: steel, geometry: {type: box, min: [0, 0, 0], max: [0.005, 0.005, 0.005]},
     spacing: 0.001, horizon_ratio: 2.015}
time: {steps: 1000}
output: {history_interval: 10}
)";
}  // namespace

TEST_CASE("check reports sizes, the limiting term and a projected time, and writes nothing",
          "[cli]") {
  const auto dir = fresh_dir("check");
  const std::string file = write_file(dir / "case.yaml", kCase);
  const auto before = std::filesystem::current_path();
  const CommandResult r = run_ckpd("check " + file + " --steps 2");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("valid") != std::string::npos);
  CHECK(r.output.find("125 points") != std::string::npos);
  CHECK(r.output.find("limited by body 'cube'") != std::string::npos);
  CHECK(r.output.find("largest term: bonds") != std::string::npos);
  CHECK(r.output.find("1000 steps") != std::string::npos);
  CHECK(r.output.find("projected run time") != std::string::npos);
  CHECK(r.output.find("MB of body data") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir / "runs"));
  CHECK_FALSE(std::filesystem::exists(before / "runs" / "case"));
}

TEST_CASE("check rejects a bad case like run does", "[cli]") {
  const auto dir = fresh_dir("check-bad");
  std::string text = kCase;
  text.replace(text.find("spacing: 0.001"), 14, "spacing: -0.001");
  const std::string file = write_file(dir / "case.yaml", text);
  const CommandResult r = run_ckpd("check " + file);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("bodies[0].spacing") != std::string::npos);
}

TEST_CASE("check prints a rigid body as rigid, without peridynamic fields", "[cli]") {
  const auto dir = fresh_dir("check-rigid");
  std::string text = kCase;
  text.replace(text.find("time:"), 0,
               "  - {name: ball, rigid: {motion: free, mass: 0.1, velocity: [0, 0, -1]},\n"
               "     geometry: {type: sphere, center: [0.0025, 0.0025, 0.009], radius: 0.002},\n"
               "     spacing: 0.001}\ncontact: {stiffness: 1e9}\n");
  const std::string file = write_file(dir / "case.yaml", text);
  const CommandResult r = run_ckpd("check " + file + " --steps 1");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const std::size_t at = r.output.find("body 'ball'");
  REQUIRE(at != std::string::npos);
  const std::string line = r.output.substr(at, r.output.find('\n', at) - at);
  CHECK(line.find("rigid, free motion, mass 0.1 kg, 3D") != std::string::npos);
  CHECK(line.find("horizon") == std::string::npos);
  CHECK(line.find("bonds") == std::string::npos);
  // The next line belongs to the next section, not a kernel note of the rigid body.
  CHECK(r.output.find("kernel:", at) > r.output.find("stable step:", at));
}
