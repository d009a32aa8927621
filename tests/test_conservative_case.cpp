// The body key `force_form` (own_family | energy_consistent, THEORY.md section 2b) in case files:
// bad values and non-CKPD models are refused with file and line; `ckpd check` and summary.json
// state the form; and what the form is for, in whole runs: two unequal discs colliding keep
// their total momentum to round-off; the undamaged strip loses the own-family energy floor of
// 0.5 % (pulled by prescribed velocities it keeps 1.6e-5 of its strain energy at every dt; set
// free its error falls like dt^2); and a tear's balance closes to second order under both
// damage rules with the case's own weights.
#include <omp.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "bodies/body.hpp"
#include "kernel_comparison.hpp"
#include "run_helpers.hpp"
#include "src/case/case_loader.hpp"
#include "src/engine/simulation.hpp"

using namespace ckpd::testing;
using ckpd::Vec3;

namespace {

// Two 2D steel discs of unequal radii (nu = 0.3: bonds and triangles) meeting at +-10 m/s.
std::string discs_case(const std::string& form) {
  return R"(# SI units
materials:
  m: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.3}
bodies:
  - {name: big, material: m, dimension: 2, geometry: {type: sphere, center: [-0.0026, 0.0004],
     radius: 0.0025}, spacing: 0.0005, horizon_ratio: 3.015, force_form: )" +
         form + R"(}
  - {name: small, material: m, dimension: 2, geometry: {type: sphere, center: [0.0018, 0],
     radius: 0.0017}, spacing: 0.0005, horizon_ratio: 3.015, force_form: )" +
         form + R"(}
conditions:
  - {type: initial_velocity, body: big, value: [10, 0]}
  - {type: initial_velocity, body: small, value: [-10, 0]}
contact: {stiffness: 1.0e12}
time: {end: 3.0e-5}
)";
}

// The strip of test_damage_rule.cpp (nu = 0.4 plane stress, 30 x 15 points), pulled apart; with
// `tear`, pre-cracked and with a fracture energy.
std::string strip_case(const std::string& form, const std::string& rule, bool tear) {
  return std::string(R"(# SI units
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.4)") +
         (tear ? ", fracture_energy: 50" : "") + R"(}
bodies:
  - name: strip
    material: steel
    dimension: 2
    geometry: {type: box, min: [0, 0], max: [0.03, 0.015]}
    spacing: 0.001
    horizon_ratio: 3.015
    damage_rule: )" +
         rule + R"(
    force_form: )" +
         form + "\n" + (tear ? "    precracks: [[[0, 0.0075], [0.01, 0.0075]]]\n" : "") + R"(
conditions:
  - {type: velocity, body: strip, region: {type: box, min: [0, 0.0135], max: [0.03, 0.015]},
     value: [0, 1], components: [y], ramp_time: 2.0e-6}
  - {type: velocity, body: strip, region: {type: box, min: [0, 0], max: [0.03, 0.0015]},
     value: [0, -1], components: [y], ramp_time: 2.0e-6}
time: {end: 3.0e-5}
)";
}

struct Run {
  double error = 0, strain = 0, dissipated = 0;
  std::size_t broken = 0;
};

Run run_in_process(const std::string& tag, const std::string& text, double safety) {
  const auto dir = fresh_dir(tag);
  const std::string file = write_file(dir / "case.yaml", text);
  ckpd::Scene scene = ckpd::load_scene(file, {"time.safety=" + std::to_string(safety)});
  ckpd::Simulation sim(scene);
  while (sim.step() < sim.planned_steps()) sim.advance(sim.step() + 1 == sim.planned_steps());
  const ckpd::Energies e = sim.energies();
  return {std::abs(e.balance_error), e.strain, e.dissipated, sim.broken_bonds()};
}

Vec3 total_momentum(const ckpd::Simulation& sim) {
  Vec3 p = Vec3::Zero();
  for (const ckpd::SceneBody& sb : sim.scene().bodies)
    for (std::size_t i = 0; i < sb.body.size(); ++i)
      p += sb.body.density * sb.body.volume[i] * sb.body.velocity[i];
  return p;
}

// The largest change of the total momentum during the collision, over the initial one.
double momentum_drift(const std::string& form) {
  const auto dir = fresh_dir("discs-" + form);
  const std::string file = write_file(dir / "case.yaml", discs_case(form));
  ckpd::Scene scene = ckpd::load_scene(file, {});
  ckpd::Simulation sim(scene);
  const Vec3 p0 = total_momentum(sim);
  double drift = 0;
  while (sim.step() < sim.planned_steps()) {
    sim.advance(sim.step() + 1 == sim.planned_steps());
    drift = std::max(drift, (total_momentum(sim) - p0).norm() / p0.norm());
  }
  // They met: the small disc was thrown back.
  const ckpd::Body& small = sim.scene().bodies[1].body;
  Vec3 p_small = Vec3::Zero();
  for (std::size_t i = 0; i < small.size(); ++i) p_small += small.volume[i] * small.velocity[i];
  REQUIRE(p_small.x() > 0);
  return drift;
}

}  // namespace

TEST_CASE("a force_form other than own_family or energy_consistent is refused with file and line",
          "[conservative]") {
  const auto dir = fresh_dir("force-form-bad");
  const std::string file =
      write_file(dir / "case.yaml", strip_case("energy", "centre_bonds", false));
  const CommandResult r = run_ckpd("check " + file);
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("case.yaml:12:") != std::string::npos);  // the line of the key
  CHECK(r.output.find("force_form") != std::string::npos);
  CHECK(r.output.find("'own_family' or 'energy_consistent'") != std::string::npos);
}

TEST_CASE("force_form energy_consistent is refused on a pmb material", "[conservative]") {
  std::string text = strip_case("energy_consistent", "centre_bonds", false);
  const std::string old = "steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.4}";
  const auto at = text.find(old);
  REQUIRE(at != std::string::npos);
  text.replace(at, old.size(), "steel: {model: pmb, density: 7850, micromodulus: 1e20}");
  const auto dir = fresh_dir("force-form-pmb");
  const CommandResult r = run_ckpd("check " + write_file(dir / "case.yaml", text));
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("case.yaml:12:") != std::string::npos);
  CHECK(r.output.find("energy_consistent is a CKPD option") != std::string::npos);
  CHECK(r.output.find("pmb") != std::string::npos);
}

TEST_CASE("ckpd check and summary.json state the force form", "[conservative]") {
  const auto dir = fresh_dir("force-form-report");
  const std::string file =
      write_file(dir / "case.yaml", strip_case("energy_consistent", "all_edges", false));
  const CommandResult c = run_ckpd("check " + file);
  INFO(c.output);
  REQUIRE(c.exit_code == 0);
  CHECK(c.output.find("force form energy_consistent") != std::string::npos);
  const CommandResult r = run_ckpd(
      "run " + file + " --quiet --threads 1 --set time.steps=5 --out " + (dir / "out").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto s = read_json(dir / "out" / "summary.json");
  CHECK(s["bodies"][0]["force_form"] == "energy_consistent");
  CHECK(s["bodies"][0]["kernel"]["force_form"] == "energy_consistent");
  CHECK(s["bodies"][0]["damage_rule"] == "all_edges");
}

TEST_CASE(
    "a body without force_form or damage_rule gets energy_consistent with all_edges on "
    "CKPD, own_family with centre_bonds on pmb",
    "[conservative]") {
  std::string text = strip_case("KEY", "KEY", true);
  for (const std::string key : {"    damage_rule: KEY\n", "    force_form: KEY\n"}) {
    const auto at = text.find(key);
    REQUIRE(at != std::string::npos);
    text.erase(at, key.size());
  }
  const auto dir = fresh_dir("force-form-default");
  const std::string file = write_file(dir / "ckpd.yaml", text);
  const ckpd::Scene ckpd_scene = ckpd::load_scene(file, {});
  CHECK(ckpd_scene.bodies[0].body.force_form == ckpd::ForceForm::energy_consistent);
  CHECK(ckpd_scene.bodies[0].body.damage_rule == ckpd::DamageRule::all_edges);
  // The seed's law by name.
  const ckpd::Scene seed = ckpd::load_scene(
      file, {"bodies.strip.force_form=own_family", "bodies.strip.damage_rule=centre_bonds"});
  CHECK(seed.bodies[0].body.force_form == ckpd::ForceForm::own_family);
  CHECK(seed.bodies[0].body.damage_rule == ckpd::DamageRule::centre_bonds);
  const std::string old =
      "steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.4, fracture_energy: 50}";
  const auto at = text.find(old);
  REQUIRE(at != std::string::npos);
  text.replace(at, old.size(),
               "steel: {model: pmb, density: 7850, micromodulus: 1e20, critical_stretch: 0.01}");
  const ckpd::Scene pmb = ckpd::load_scene(write_file(dir / "pmb.yaml", text), {});
  CHECK(pmb.bodies[0].body.force_form == ckpd::ForceForm::own_family);
  CHECK(pmb.bodies[0].body.damage_rule == ckpd::DamageRule::centre_bonds);
}

TEST_CASE("two unequal discs colliding keep their total momentum under energy_consistent",
          "[conservative]") {
  kernel_comparison::ThreadCountGuard guard;
  omp_set_num_threads(1);
  const double ec = momentum_drift("energy_consistent");
  const double own = momentum_drift("own_family");
  INFO("largest relative change of the total momentum: energy_consistent " << ec << ", own_family "
                                                                           << own);
  CHECK(ec < 1e-12);
  CHECK(own > 1e-8);
}

TEST_CASE("the undamaged strip's energy balance has no own-family floor under energy_consistent",
          "[conservative]") {
  kernel_comparison::ThreadCountGuard guard;
  omp_set_num_threads(1);
  const std::string ec = strip_case("energy_consistent", "centre_bonds", false);
  const std::string own = strip_case("own_family", "centre_bonds", false);
  const Run coarse = run_in_process("strip-ec", ec, 0.8);
  const Run fine = run_in_process("strip-ec-fine", ec, 0.4);
  const Run own_coarse = run_in_process("strip-own", own, 0.8);
  const Run own_fine = run_in_process("strip-own-fine", own, 0.4);
  INFO("pulled strip, strain energy "
       << coarse.strain << " J/m. energy_consistent: balance error " << coarse.error << " (dt), "
       << fine.error << " (dt/2); own_family: " << own_coarse.error << ", " << own_fine.error);
  // Measured: 0.014 and 0.013 J/m (1.6e-5 of the strain energy, left by the prescribed
  // velocities' work, not by the forces: the free strip below converges) against the
  // own-family floor of 4.0 J/m (0.5 %) at both steps.
  CHECK(coarse.error < 1e-4 * coarse.strain);
  CHECK(fine.error < 1e-4 * fine.strain);
  CHECK(own_coarse.error > 3e-3 * own_coarse.strain);
  CHECK(own_fine.error > 0.5 * own_coarse.error);  // the own-family floor does not fall
  // The same strip set free with the pull's velocities: the error falls like dt^2.
  std::string free = ec;
  for (std::size_t at; (at = free.find("{type: velocity")) != std::string::npos;)
    free.replace(at, 15, "{type: initial_velocity");
  const std::string ramp = ", components: [y], ramp_time: 2.0e-6";
  for (std::size_t at; (at = free.find(ramp)) != std::string::npos;) free.erase(at, ramp.size());
  const Run free_coarse = run_in_process("strip-free", free, 0.8);
  const Run free_fine = run_in_process("strip-free-fine", free, 0.4);
  INFO("free strip: balance error " << free_coarse.error << " (dt), " << free_fine.error
                                    << " (dt/2)");
  CHECK(free_fine.error < 0.3 * free_coarse.error);  // second order: 0.25
}

TEST_CASE("a tear's energy balance closes to second order under energy_consistent, either rule",
          "[conservative]") {
  kernel_comparison::ThreadCountGuard guard;
  omp_set_num_threads(1);
  for (const std::string rule : {"centre_bonds", "all_edges"}) {
    const Run coarse =
        run_in_process("tear-ec-" + rule, strip_case("energy_consistent", rule, true), 0.8);
    const Run fine =
        run_in_process("tear-ec-fine-" + rule, strip_case("energy_consistent", rule, true), 0.4);
    INFO(rule << ": " << coarse.broken << " bonds broken, dissipated " << coarse.dissipated
              << " J/m, balance error " << coarse.error << " (dt), " << fine.error << " (dt/2)");
    REQUIRE(coarse.broken > 300);
    CHECK(coarse.error < 0.03 * coarse.dissipated);
    CHECK(fine.error < 0.35 * coarse.error);
  }
}
