// Case and sweep files are read within bounds (src/input/yaml_document.hpp): an alias inside
// the node it names, an alias bomb, a file of hundreds of thousands of values and nesting past
// the depth guard are refused at once with the file and line, exit 2; anchors and aliases that
// only repeat a value still work.
#include <catch2/catch.hpp>
#include <fstream>

#include "ball_fixture.hpp"
#include "run_helpers.hpp"
#include "src/input/case_node.hpp"
#include "src/input/yaml_document.hpp"

using namespace ckpd;
using namespace ckpd::testing;

namespace {

const std::string kBall = steel_ball_case("time: {steps: 3}\n");

std::string refusal(const std::string& file) {
  try {
    load_yaml_file(file, "case file");
  } catch (const CaseError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("an alias inside the node it names is refused with its line", "[yaml]") {
  const auto dir = fresh_dir("yaml-cycle");
  const std::string file = write_file(dir / "case.yaml", "x: &x [*x]\n");
  CHECK_THAT(refusal(file), Catch::Contains("case.yaml:1: an alias inside the node its anchor"));
  // `ckpd check` walked the list for ever.
  const TimedResult r = run_ckpd_within(20, "check " + file);
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Catch::Contains("contains itself"));
  CHECK(r.seconds < 5);
  // The same as a --set value.
  const std::string ball = write_file(dir / "ball.yaml", kBall);
  const TimedResult s = run_ckpd_within(20, "check " + ball + " --set 'description=&d [*d]'");
  INFO(s.output);
  CHECK(s.exit_code == 2);
  CHECK_THAT(s.output, Catch::Contains("--set description=&d [*d]:1: an alias inside"));
}

TEST_CASE("an alias bomb under an unknown key is refused before it expands", "[yaml]") {
  const std::string file = std::string(CKPD_SOURCE_DIR) + "/tests/data/inputs/alias_bomb.yaml";
  CHECK_THAT(refusal(file),
             Catch::Contains("alias_bomb.yaml:") && Catch::Contains("more than 200000 values"));
  const TimedResult r = run_ckpd_within(30, "check " + file);
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.seconds < 5);
}

TEST_CASE("a case of a hundred thousand pre-cracks is refused at once, naming the line", "[yaml]") {
  // A 3 MB file took 430 MB and 9-18 s before anything was said.
  const auto dir = fresh_dir("yaml-size");
  std::ofstream out(dir / "case.yaml");
  out << "materials:\n  steel: {density: 7850, youngs_modulus: 210e9, poisson_ratio: 0.3}\n"
         "bodies:\n  - name: plate\n    material: steel\n    dimension: 2\n"
         "    geometry: {type: box, min: [0, 0], max: [0.01, 0.01]}\n"
         "    spacing: 0.001\n    horizon_ratio: 3.015\n    precracks:\n";
  for (int k = 0; k < 100000; ++k)
    out << "      - [[0.001, " << 1e-7 * k << "], [0.002, " << 1e-7 * k << "]]\n";
  out << "time: {steps: 1}\n";
  out.close();
  const TimedResult r = run_ckpd_within(60, "check " + (dir / "case.yaml").string());
  INFO(r.output.substr(0, 2000));
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output,
             Catch::Contains("case.yaml:") && Catch::Contains("holds more than 200000 values"));
  CHECK(r.seconds < 5);
}

TEST_CASE("anchors and aliases that repeat a value are read as the value", "[yaml]") {
  const auto dir = fresh_dir("yaml-alias");
  std::string text = kBall;
  text.replace(text.find("steel: {"), 6, "steel: &steel_props");
  text.replace(text.find("bodies:"), 7, "  steel2: *steel_props\nbodies:");
  const std::string file = write_file(dir / "case.yaml", text);
  const YAML::Node root = load_yaml_file(file, "case file");
  CHECK(root["materials"]["steel2"]["density"].as<double>() == 7850);
  const CommandResult r = run_ckpd("check " + file + " --steps 1");
  INFO(text << "\n" << r.output);
  CHECK(r.exit_code == 0);
}

TEST_CASE("the value count follows what each alias stands for", "[yaml]") {
  // Ten lists of ten aliases to the list before: 10^5 values through aliases pass, 10^6 do not.
  auto nested = [](int levels) {
    std::string text = "a0: &a0 [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]\n";
    for (int k = 1; k < levels; ++k) {
      const std::string prev = "*a" + std::to_string(k - 1);
      text += "a" + std::to_string(k) + ": &a" + std::to_string(k) + " [";
      for (int i = 0; i < 10; ++i) text += (i ? ", " : "") + prev;
      text += "]\n";
    }
    return text;
  };
  const auto dir = fresh_dir("yaml-count");
  CHECK(refusal(write_file(dir / "small.yaml", nested(4))).empty());
  CHECK_THAT(refusal(write_file(dir / "large.yaml", nested(6))),
             Catch::Contains("large.yaml:6: the document holds more than 200000 values"));
}
