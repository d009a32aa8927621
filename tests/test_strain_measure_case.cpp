// `strain_measure: {m: M}` on a CKPD material (src/case/materials/ckpd_material.cpp): it reaches
// the body (summary.json's kernel entry, `ckpd check`), changes the run, and bad values are
// refused naming file, line and key; a pmb material has no strain measure.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>

#include "run_helpers.hpp"

using namespace ckpd::testing;

namespace {

// A small 2D plate whose top rows are pulled up, SI units; MEASURE is replaced by the key under
// test. nu = 0.4 in plane stress: C2 > 0, as m <= 0 needs (a negative C2 is refused).
const char* kCase = R"(# a small 2D plate, SI units
materials:
  steel: {MEASURE density: 7580, youngs_modulus: 210e9, poisson_ratio: 0.4}
bodies:
  - name: plate
    material: steel
    dimension: 2
    geometry: {type: box, min: [0, 0], max: [0.05, 0.05]}
    spacing: 0.005
    horizon_ratio: 3.015
conditions:
  - {type: velocity, body: plate, region: {type: box, min: [0, 0.045], max: [0.05, 0.05]},
     value: [0, 20], components: [y]}
time: {steps: 20}
)";

std::string with_measure(const std::string& key) {
  std::string text = kCase;
  return text.replace(text.find("MEASURE "), 8, key);
}

void replace_once(std::string& text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  REQUIRE(at != std::string::npos);
  text.replace(at, from.size(), to);
}

CommandResult run_case(const std::string& text, const std::filesystem::path& dir,
                       const std::string& command = "run") {
  const std::string file = write_file(dir / "case.yaml", text);
  return run_ckpd(command + " " + file + " --quiet --out " + (dir / "out").string());
}

}  // namespace

TEST_CASE("strain_measure on a material reaches the body and summary.json", "[strain_measure]") {
  const auto a = fresh_dir("sm-default"), b = fresh_dir("sm-half"), c = fresh_dir("sm-log");
  const CommandResult plain = run_case(with_measure(""), a);
  const CommandResult half = run_case(with_measure("strain_measure: {m: 0.5}, "), b);
  const CommandResult log = run_case(with_measure("strain_measure: {m: 0}, "), c);
  INFO(plain.output << half.output << log.output);
  REQUIRE(plain.exit_code == 0);
  REQUIRE(half.exit_code == 0);
  REQUIRE(log.exit_code == 0);
  const auto s0 = read_json(a / "out" / "summary.json"), sh = read_json(b / "out" / "summary.json"),
             sl = read_json(c / "out" / "summary.json");
  CHECK(s0["bodies"][0]["kernel"]["model"] == "ckpd");
  CHECK(s0["bodies"][0]["kernel"]["strain_measure"]["m"] == 0.5);
  CHECK(sl["bodies"][0]["kernel"]["strain_measure"]["m"] == 0.0);
  CHECK(s0["energy"] == sh["energy"]);  // m = 1/2 is the default law, bit for bit
  CHECK(s0["dt"] == sl["dt"]);          // the stable step does not depend on m
  CHECK(s0["energy"]["strain"] != sl["energy"]["strain"]);  // m = 0 is another law
}

TEST_CASE("ckpd check names the strain measure", "[strain_measure][cli]") {
  const auto dir = fresh_dir("sm-check");
  const std::string file =
      write_file(dir / "case.yaml", with_measure("strain_measure: {m: -0.5}, "));
  const CommandResult r = run_ckpd("check " + file);
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(r.output.find("strain measure m = -0.5") != std::string::npos);
}

TEST_CASE("a barrier measure on a material with a negative set constant is refused",
          "[strain_measure]") {
  // m <= 0 with C2 < 0 (plane stress nu < 1/3) or C3 < 0 (3D nu < 1/4): the sets' energy goes to
  // minus infinity as they collapse. m = 1/2 (bounded energy) and m > 0 are accepted.
  struct Row {
    const char* m;
    const char* nu;
    const char* geometry;  // "" keeps the 2D plate
    int exit_code;
    const char* constant;
  };
  const std::string three_d =
      "dimension: 3\n    geometry: {type: box, min: [0, 0, 0], max: [0.02, 0.02, 0.02]}";
  for (const Row& row : {Row{"0", "0.3", "", 2, "C2 = -"}, Row{"-0.5", "0.2", "", 2, "C2 = -"},
                         Row{"-0.5", "0.2", "3d", 2, "C3 = -"}, Row{"0.5", "0.3", "", 0, ""},
                         Row{"0.25", "0.2", "3d", 0, ""}, Row{"0", "0.3", "3d", 0, ""}}) {
    const auto dir = fresh_dir("sm-anti");
    std::string text = with_measure(std::string("strain_measure: {m: ") + row.m + "}, ");
    replace_once(text, "poisson_ratio: 0.4", std::string("poisson_ratio: ") + row.nu);
    if (std::string(row.geometry) == "3d") {
      const std::string plate =
          "dimension: 2\n    geometry: {type: box, min: [0, 0], max: [0.05, 0.05]}";
      replace_once(text, plate, three_d);
      replace_once(text, "min: [0, 0.045], max: [0.05, 0.05]",
                   "min: [0, 0, 0.015], max: [0.02, 0.02, 0.02]");
      replace_once(text, "value: [0, 20]", "value: [0, 0, 20]");
      replace_once(text, "components: [y]", "components: [z]");
      replace_once(text, "time: {steps: 20}", "time: {steps: 2}");
    }
    const CommandResult r = run_ckpd("check " + write_file(dir / "case.yaml", text));
    INFO("m = " << row.m << ", nu = " << row.nu << " " << row.geometry << ": " << r.output);
    CHECK(r.exit_code == row.exit_code);
    if (row.exit_code == 2) {
      CHECK(r.output.find("case.yaml:3: materials.steel.strain_measure.m") != std::string::npos);
      CHECK(r.output.find(row.constant) != std::string::npos);
      CHECK(r.output.find("minus infinity") != std::string::npos);
    }
  }
}

TEST_CASE("a strain measure that is not a number is refused with file, line and key",
          "[strain_measure]") {
  for (const char* bad : {"strain_measure: {m: log}, ", "strain_measure: {m: .nan}, "}) {
    const auto dir = fresh_dir("sm-bad");
    const CommandResult r = run_case(with_measure(bad), dir);
    INFO(bad << ": " << r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("case.yaml:3") != std::string::npos);
    CHECK(r.output.find("materials.steel.strain_measure.m") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir / "out" / "summary.json"));
  }
}

TEST_CASE("a strain measure outside [-2, 2] is refused with file, line and key",
          "[strain_measure]") {
  // m = 1e6 overflowed r^(2m) at the first strain and the run stopped with null energies.
  for (const char* bad : {"strain_measure: {m: 1.0e6}, ", "strain_measure: {m: -2.5}, "}) {
    const auto dir = fresh_dir("sm-range");
    const CommandResult r = run_case(with_measure(bad), dir);
    INFO(bad << ": " << r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("case.yaml:3: materials.steel.strain_measure.m: expected a Seth-Hill "
                        "exponent m from -2 to 2") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir / "out" / "summary.json"));
  }
  for (const char* good : {"strain_measure: {m: 2}, ", "strain_measure: {m: -2}, "}) {
    const auto dir = fresh_dir("sm-range-ends");
    const CommandResult r =
        run_ckpd("check " + write_file(dir / "case.yaml", with_measure(good)) + " --steps 1");
    INFO(good << ": " << r.output);
    CHECK(r.exit_code == 0);
  }
}

TEST_CASE("a strain measure must be a map with m and nothing else", "[strain_measure]") {
  {
    const auto dir = fresh_dir("sm-scalar");
    const CommandResult r = run_case(with_measure("strain_measure: 0, "), dir);
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("materials.steel.strain_measure") != std::string::npos);
    CHECK(r.output.find("{m: M}") != std::string::npos);
  }
  {
    const auto dir = fresh_dir("sm-missing");
    const CommandResult r = run_case(with_measure("strain_measure: {}, "), dir);
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("materials.steel.strain_measure: missing required key 'm'") !=
          std::string::npos);
  }
  {
    const auto dir = fresh_dir("sm-extra");
    const CommandResult r = run_case(with_measure("strain_measure: {m: 0, n: 1}, "), dir);
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("materials.steel.strain_measure.n") != std::string::npos);
  }
}

TEST_CASE("a pmb material has no strain measure", "[strain_measure]") {
  const auto dir = fresh_dir("sm-pmb");
  std::string text = kCase;
  text.replace(
      text.find("MEASURE density: 7580, youngs_modulus: 210e9, poisson_ratio: 0.4"),
      std::string("MEASURE density: 7580, youngs_modulus: 210e9, poisson_ratio: 0.4").size(),
      "model: pmb, density: 7580, micromodulus: 1e20, strain_measure: {m: 0}");
  const CommandResult r = run_case(text, dir);
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("materials.steel.strain_measure") != std::string::npos);
}

TEST_CASE("a plate crushed with the log measure completes finite or stops as unstable",
          "[strain_measure]") {
  // The stable step is the reference-state estimate for every m, while m = 0 stiffens in
  // compression: the run must either stay finite or be stopped by the instability guard, never
  // write non-finite figures as a completed run. The top rows move down 40 % of the height.
  for (const char* m : {"0", "-0.5"}) {
    const auto dir = fresh_dir("sm-crush");
    std::string text = with_measure(std::string("strain_measure: {m: ") + m + "}, ");
    replace_once(text, "value: [0, 20]", "value: [0, -300]");
    text.replace(text.find("time: {steps: 20}"), 17,
                 "time: {end: 6.0e-5}\n"
                 "output: {history_interval: 10}");
    text.replace(text.find("conditions:\n"), 12,
                 "conditions:\n  - {type: fixed, body: plate, region: {type: box, min: [0, 0], "
                 "max: [0.05, 0.005]}}\n");
    const CommandResult r = run_case(text, dir);
    INFO("m = " << m << ": " << r.output);
    REQUIRE((r.exit_code == 0 || r.exit_code == 3));
    const auto s = read_json(dir / "out" / "summary.json");
    if (r.exit_code == 0) {
      CHECK(s["status"] == "completed");
      for (const auto& [key, value] : s["energy"].items()) {
        INFO(key);
        REQUIRE(value.is_number());
        CHECK(std::isfinite(value.get<double>()));
      }
    } else {
      CHECK(s["status"] == "unstable");
      CHECK(r.output.find("instability at step") != std::string::npos);
    }
  }
}
