// Bad input gets a clear error naming the file, the key (and line) and what was expected, and a
// non-zero exit without results that pass for complete.
#include <catch2/catch.hpp>
#include <filesystem>

#include "run_helpers.hpp"

using namespace ckpd::testing;

namespace {

const char* kGoodCase = R"(# a small 2D plate, SI units
materials:
  steel: {density: 7580, youngs_modulus: 210e9, poisson_ratio: 0.3, fracture_energy: 140}
bodies:
  - name: plate
    material: steel
    dimension: 2
    geometry: {type: box, min: [0, 0], max: [0.05, 0.05]}
    spacing: 0.005
    horizon_ratio: 3.015
time: {steps: 5}
)";

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

// Runs a case and expects failure with every fragment in the message and no summary written.
void expect_rejected(const std::string& case_text, std::initializer_list<std::string> fragments) {
  const auto dir = fresh_dir("bad");
  const std::string file = write_file(dir / "case.yaml", case_text);
  const CommandResult r = run_ckpd("run " + file + " --out " + (dir / "out").string());
  INFO(r.output);
  CHECK(r.exit_code == 2);
  for (const std::string& f : fragments) CHECK(r.output.find(f) != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir / "out" / "summary.json"));
}

}  // namespace

TEST_CASE("the good case runs, so the rejections below are about their one change", "[cli]") {
  const auto dir = fresh_dir("good");
  const std::string file = write_file(dir / "case.yaml", kGoodCase);
  const CommandResult r = run_ckpd("run " + file + " --quiet --out " + (dir / "out").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(read_json(dir / "out" / "summary.json")["status"] == "completed");
}

TEST_CASE("a missing case file is an error naming the file", "[cli]") {
  const CommandResult r = run_ckpd("run /nonexistent/case.yaml");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("/nonexistent/case.yaml") != std::string::npos);
  CHECK(r.output.find("not found") != std::string::npos);
}

TEST_CASE("a YAML syntax error names the line", "[cli]") {
  expect_rejected(replace(kGoodCase, "time: {steps: 5}", "time: {steps: 5"),
                  {"case.yaml:", "YAML syntax error"});
}

TEST_CASE("an unknown key is an error naming the key and its line", "[cli]") {
  expect_rejected(replace(kGoodCase, "    spacing: 0.005", "    spacing: 0.005\n    spacnig: 1"),
                  {"case.yaml:10:", "bodies[0].spacnig", "unknown key"});
}

TEST_CASE("a non-positive Young's modulus is rejected", "[cli]") {
  expect_rejected(replace(kGoodCase, "youngs_modulus: 210e9", "youngs_modulus: -1"),
                  {"materials.steel.youngs_modulus", "positive"});
  expect_rejected(replace(kGoodCase, "youngs_modulus: 210e9", "youngs_modulus: 0"),
                  {"materials.steel.youngs_modulus", "positive"});
}

TEST_CASE("a Poisson's ratio of 0.5 or more is rejected", "[cli]") {
  expect_rejected(replace(kGoodCase, "poisson_ratio: 0.3", "poisson_ratio: 0.5"),
                  {"materials.steel.poisson_ratio", "(-1, 0.5)"});
}

TEST_CASE("a horizon smaller than the spacing is rejected", "[cli]") {
  expect_rejected(replace(kGoodCase, "horizon_ratio: 3.015", "horizon_ratio: 0.8"),
                  {"bodies[0].horizon_ratio", "at least the spacing"});
}

TEST_CASE("a body with no usable points is rejected", "[cli]") {
  // Smaller than one lattice cell: a single point, which has no bond.
  expect_rejected(replace(kGoodCase, "{type: box, min: [0, 0], max: [0.05, 0.05]}",
                          "{type: sphere, center: [0, 0], radius: 0.001}"),
                  {"case.yaml:5: bodies[0]", "has no neighbour within the horizon"});
}

TEST_CASE("a sampling over the point limit is refused with the estimate", "[cli]") {
  expect_rejected(replace(kGoodCase, "max: [0.05, 0.05]}", "max: [0.05, 0.05]}\n    max_points: 3"),
                  {"bodies[0].geometry", "about 100 lattice sites", "over the limit of 3"});
}

TEST_CASE("a value of the wrong kind names what was expected", "[cli]") {
  expect_rejected(replace(kGoodCase, "spacing: 0.005", "spacing: fine"),
                  {"bodies[0].spacing", "expected a number", "'fine'"});
  expect_rejected(replace(kGoodCase, "min: [0, 0]", "min: [0, 0, 0]"),
                  {"bodies[0].geometry.min", "list of 2 numbers"});
}

TEST_CASE("a condition naming an unknown body or an empty region is rejected", "[cli]") {
  std::string text = kGoodCase;
  text += "conditions:\n  - {type: fixed, body: plat}\n";
  expect_rejected(text, {"conditions[0].body", "name of a body"});
  text = kGoodCase;
  text +=
      "conditions:\n  - {type: fixed, body: plate, region: {type: box, min: [1, 1], max: [2, "
      "2]}}\n";
  expect_rejected(text, {"conditions[0].region", "holds no point"});
}

TEST_CASE("a time step above the stable estimate is refused unless forced", "[cli]") {
  expect_rejected(replace(kGoodCase, "time: {steps: 5}", "time: {steps: 5, dt: 1.0}"),
                  {"exceeds the stable-step estimate", "allow_unstable_dt"});
}

TEST_CASE("a --set override changes a value, and a path that does not exist is rejected", "[cli]") {
  const auto dir = fresh_dir("set");
  const std::string file = write_file(dir / "case.yaml", kGoodCase);
  CommandResult r = run_ckpd("run " + file + " --quiet --out " + (dir / "out").string() +
                             " --set time.steps=3 --set bodies.plate.spacing=0.01");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto summary = read_json(dir / "out" / "summary.json");
  CHECK(summary["steps"] == 3);
  CHECK(summary["points"] == 25);  // 0.05 m / 0.01 m = 5 per side
  r = run_ckpd("run " + file + " --quiet --out " + (dir / "out2").string() +
               " --set bodies.slab.spacing=0.01");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("no element 'slab'") != std::string::npos);
  r = run_ckpd("run " + file + " --quiet --out " + (dir / "out2").string() + " --set time.stpes=3");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("time.stpes") != std::string::npos);
}

TEST_CASE("a body's constants must be 'analytic' or 'calibrated'", "[cli][calibration]") {
  const auto dir = fresh_dir("calibrated");
  const std::string file = write_file(
      dir / "case.yaml", replace(kGoodCase, "    horizon_ratio: 3.015\n",
                                 "    horizon_ratio: 3.015\n    constants: calibrated\n"));
  const CommandResult r = run_ckpd("run " + file + " --quiet --out " + (dir / "out").string());
  INFO(r.output);
  CHECK(r.exit_code == 0);
  // summary.json records the constants in use: the calibrated C1 is not the analytic one.
  const std::string plain = write_file(dir / "plain.yaml", kGoodCase);
  REQUIRE(run_ckpd("run " + plain + " --quiet --out " + (dir / "plain").string()).exit_code == 0);
  const auto calibrated_c1 =
      read_json(dir / "out" / "summary.json")["bodies"][0]["constants"]["c1"];
  const auto analytic_c1 =
      read_json(dir / "plain" / "summary.json")["bodies"][0]["constants"]["c1"];
  CHECK(calibrated_c1.get<double>() > 0);
  CHECK(analytic_c1.get<double>() > 0);
  CHECK(calibrated_c1.get<double>() != analytic_c1.get<double>());
  expect_rejected(replace(kGoodCase, "    horizon_ratio: 3.015\n",
                          "    horizon_ratio: 3.015\n    constants: fitted\n"),
                  {"case.yaml:11:", "constants", "'analytic' or 'calibrated'"});
}

TEST_CASE("a body's damage_rule and lattice_stencil take only their named values", "[cli]") {
  expect_rejected(replace(kGoodCase, "    horizon_ratio: 3.015\n",
                          "    horizon_ratio: 3.015\n    damage_rule: every_bond\n"),
                  {"case.yaml:11:", "damage_rule", "'centre_bonds' or 'all_edges'"});
  expect_rejected(replace(kGoodCase, "    horizon_ratio: 3.015\n",
                          "    horizon_ratio: 3.015\n    lattice_stencil: maybe\n"),
                  {"case.yaml:11:", "lattice_stencil", "'maybe'"});
}
