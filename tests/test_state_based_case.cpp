// `model: state_based` in case files (src/case/materials/state_based_material.cpp): it reaches
// the body (summary.json's kernel entry, `ckpd check`), its free-surface field is written, a
// tearing run keeps the energy balance with the failure energy booked, a restart continues bit
// for bit, and bad input is refused naming file, line and key.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "run_helpers.hpp"

using namespace ckpd::testing;

namespace {

// A pre-cracked 2D strip torn apart, SI units; MATERIAL is replaced by the material's keys.
const char* kTear = R"(# a pre-cracked 2D strip torn apart, SI units
materials:
  pmma: {MATERIAL}
bodies:
  - name: strip
    material: pmma
    dimension: 2
    geometry: {type: box, min: [0, 0], max: [0.04, 0.02]}
    spacing: 0.001
    horizon_ratio: 3.015
    precracks: [[[0, 0.01], [0.015, 0.01]]]
conditions:
  - {type: velocity, body: strip, region: {type: box, min: [0, 0.018], max: [0.04, 0.02]},
     value: [0, 2], components: [y], ramp_time: 2.0e-6}
  - {type: velocity, body: strip, region: {type: box, min: [0, 0], max: [0.04, 0.002]},
     value: [0, -2], components: [y], ramp_time: 2.0e-6}
time: {end: 4.0e-5}
output: {history_interval: 20, checkpoint_interval: 20}
)";

const char* kMaterial =
    "model: state_based, density: 1180, lambda_bar: 2.0e9, mu_bar: 2.5e9, fracture_energy: 50";

std::string with_material(const std::string& keys) {
  std::string text = kTear;
  return text.replace(text.find("MATERIAL"), 8, keys);
}

CommandResult run_case(const std::string& text, const std::filesystem::path& dir,
                       const std::string& extra = "") {
  const std::string file = write_file(dir / "case.yaml", text);
  return run_ckpd("run " + file + " --quiet --out " + (dir / "out").string() + " " + extra);
}

}  // namespace

TEST_CASE("a state_based material reaches the body, summary.json and ckpd check",
          "[state_based][case]") {
  const auto dir = fresh_dir("sb-summary");
  std::string text = with_material(std::string(kMaterial) + ", strain_measure: {m: 0}");
  text.replace(text.find("output: {history_interval: 20, checkpoint_interval: 20}"), 55,
               "output: {history_interval: 20, field_interval: 100, fields: [free_surface, "
               "damage]}");
  const CommandResult r = run_case(text, dir);
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto s = read_json(dir / "out" / "summary.json");
  CHECK(s["bodies"][0]["kernel"]["model"] == "state_based");
  CHECK(s["bodies"][0]["kernel"]["strain_measure"]["m"] == 0.0);
  CHECK(s["broken_bonds"].get<long long>() > 0);  // the crack grew by the energy criterion
  std::ifstream xdmf(dir / "out" / "fields.xdmf");
  const std::string index((std::istreambuf_iterator<char>(xdmf)), std::istreambuf_iterator<char>());
  CHECK(index.find("free_surface") != std::string::npos);

  const std::string file = (dir / "case.yaml").string();
  const CommandResult check = run_ckpd("check " + file);
  INFO(check.output);
  CHECK(check.exit_code == 0);
  CHECK(check.output.find("state_based model (strain measure m = 0)") != std::string::npos);
}

TEST_CASE("a state_based tearing run keeps the energy balance with the failure energy booked",
          "[state_based][energy]") {
  // As for CKPD (test_energy_balance.cpp): the failure energy booked at the step's midpoint
  // leaves an error second order in dt.
  for (const char* m : {"0.5", "0"}) {
    auto run = [&](const std::string& extra) {
      const auto dir = fresh_dir("sb-balance");
      const CommandResult r =
          run_case(with_material(std::string(kMaterial) + ", strain_measure: {m: " + m + "}"), dir,
                   "--threads 1 " + extra);
      INFO("m = " << m << ": " << r.output);
      REQUIRE(r.exit_code == 0);
      return read_json(dir / "out" / "summary.json")["energy"];
    };
    const auto coarse = run(""), fine = run("--set time.safety=0.4");
    INFO(coarse.dump() << "\n" << fine.dump());
    const double dissipated = coarse["dissipated"].get<double>();
    const double error_coarse = std::abs(coarse["balance_error"].get<double>());
    const double error_fine = std::abs(fine["balance_error"].get<double>());
    std::cout << "state-based tear, m = " << m << ": dissipated " << dissipated
              << " J/m, balance error " << error_coarse << " (dt) and " << error_fine
              << " (dt/2) J/m\n";
    REQUIRE(dissipated > 0.3 * coarse["external_work"].get<double>());
    CHECK(error_coarse < 0.06 * dissipated);
    CHECK(error_fine < 0.3 * error_coarse);  // about second order
  }
}

TEST_CASE("a state_based run and a restart half way give the same run bit for bit",
          "[state_based][restart]") {
  const auto dir = fresh_dir("sb-restart");
  const std::string file = write_file(dir / "case.yaml", with_material(kMaterial));
  CommandResult r =
      run_ckpd("run " + file + " --quiet --threads 2 --out " + (dir / "full").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto full = read_json(dir / "full" / "summary.json");
  const long long steps = full["steps"].get<long long>();
  r = run_ckpd("run " + file + " --quiet --threads 2 --set time.steps=" +
               std::to_string(steps / 2) + " --out " + (dir / "part").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  std::filesystem::copy_file(dir / "part" / "checkpoint.h5", dir / "half.h5");
  r = run_ckpd("run " + file + " --quiet --threads 2 --restart " + (dir / "half.h5").string() +
               " --out " + (dir / "part").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto resumed = read_json(dir / "part" / "summary.json");
  CHECK(resumed["steps"] == full["steps"]);
  CHECK(resumed["broken_bonds"] == full["broken_bonds"]);
  CHECK(resumed["energy"] == full["energy"]);
}

TEST_CASE("state_based and CKPD materials refuse each other's keys, naming file, line and key",
          "[state_based][case]") {
  struct Bad {
    std::string keys, where, says;
  };
  const std::vector<Bad> cases = {
      {std::string(kMaterial) + ", strain_measure: {m: log}", "materials.pmma.strain_measure.m",
       "expected a number"},
      {"model: state_based, density: 1180, lambda_bar: 2.0e9, mu_bar: 2.5e9, critical_stretch: "
       "0.01",
       "materials.pmma.critical_stretch", "fracture_energy"},
      {"model: state_based, density: 1180, lambda_bar: 2.0e9, mu_bar: 2.5e9, youngs_modulus: "
       "3e9, poisson_ratio: 0.3",
       "materials.pmma", "not both"},
      {"model: state_based, density: 1180, lambda_bar: 2.0e9", "materials.pmma",
       "missing required key 'mu_bar'"},
      {"model: state_based, density: 1180, lambda_bar: -3.0e9, mu_bar: 2.5e9",
       "materials.pmma.lambda_bar", "positive bulk response"},
      {"density: 1180, youngs_modulus: 3e9, poisson_ratio: 0.3, lambda_bar: 2e9",
       "materials.pmma.lambda_bar", "state_based"},
      {"model: pmb, density: 1180, micromodulus: 1e20, mu_bar: 2e9", "materials.pmma.mu_bar",
       "state_based"},
  };
  for (const Bad& bad : cases) {
    const auto dir = fresh_dir("sb-bad");
    const CommandResult r = run_case(with_material(bad.keys), dir);
    INFO(bad.keys << "\n" << r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("case.yaml:3") != std::string::npos);
    CHECK(r.output.find(bad.where) != std::string::npos);
    CHECK(r.output.find(bad.says) != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir / "out" / "summary.json"));
  }
  // The body-level CKPD option.
  const auto dir = fresh_dir("sb-penalty");
  std::string text = with_material(kMaterial);
  text.replace(text.find("    horizon_ratio: 3.015\n"), 25,
               "    horizon_ratio: 3.015\n    inversion_penalty: 1\n");
  const CommandResult r = run_case(text, dir);
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("case.yaml:") != std::string::npos);
  CHECK(r.output.find("an inversion penalty is a CKPD option") != std::string::npos);
}

TEST_CASE(
    "with m <= 0 the stable-step guard stops a run past the current stable step and names "
    "the safety that holds",
    "[state_based][stable_step]") {
  // A small Riemann bar (cases/riemann_bar_2d.yaml in miniature): the halves meet at +-1200 m/s
  // and the log strain stiffens at the interface in the first step.
  const char* kBar = R"(# SI units, 2D per unit thickness
materials:
  sb: {model: state_based, density: 1180, lambda_bar: 10.0e9, mu_bar: 10.0e9, strain_measure: {m: 0}}
  ck: {density: 1180, youngs_modulus: 13.75e9, poisson_ratio: 0.375, strain_measure: {m: 0}}
bodies:
  - {name: bar, material: MATERIAL, dimension: 2, plane: strain,
     geometry: {type: box, min: [-0.1, -0.05], max: [0.1, 0.05]}, spacing: 0.0125, horizon: 0.05}
conditions:
  - {type: initial_velocity, body: bar, region: {type: box, min: [-0.2, -0.1], max: [0.0, 0.1]},
     value: [1200, 0]}
  - {type: initial_velocity, body: bar, region: {type: box, min: [0.0, -0.1], max: [0.2, 0.1]},
     value: [-1200, 0]}
time: {steps: 3}
)";
  // CKPD under both force forms (energy_consistent is the case default).
  for (const char* material : {"sb", "ck", "ck, force_form: own_family"}) {
    std::string text = kBar;
    text.replace(text.find("MATERIAL"), 8, material);
    const auto dir = fresh_dir("sb-guard");
    const CommandResult r = run_case(text, dir);
    INFO(material << ": " << r.output);
    REQUIRE(r.exit_code == 3);
    CHECK(r.output.find("which stiffens in compression") != std::string::npos);
    const std::size_t at = r.output.find("time.safety <= ");
    REQUIRE(at != std::string::npos);
    const double safety = std::stod(r.output.substr(at + 15));
    REQUIRE(safety > 0);
    REQUIRE(safety < 0.8);
    // At the named safety the first step is taken.
    const auto again = fresh_dir("sb-guard");
    const CommandResult ok = run_case(
        text, again, "--set time.safety=" + std::to_string(0.99 * safety) + " --set time.steps=1");
    INFO(ok.output);
    CHECK(ok.exit_code == 0);
  }
}
