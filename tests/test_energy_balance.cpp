// The energy balance of history.csv / summary.json: kinetic + strain + contact + dissipated -
// external work stays at its initial value. Elastic impacts close it to the integrator's
// O(dt^2); with bonds breaking, the energy of the lost interactions is booked as dissipated at
// the midpoint of the step in which they fail, which is what the integrator actually removes
// (bodies/damage.hpp): booked at the step's end instead, the balance kept a first-order error of
// 20 % of the dissipated energy in the tearing test below.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>

#include "run_helpers.hpp"

using namespace ckpd::testing;

namespace {

nlohmann::json run_case(const std::string& tag, const std::string& text,
                        const std::string& extra = "") {
  const auto dir = fresh_dir(tag);
  const std::string file = write_file(dir / "case.yaml", text);
  const CommandResult r = run_ckpd("run " + file + " --quiet --threads 1 --out " +
                                   (dir / "out").string() + " " + extra);
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  return read_json(dir / "out" / "summary.json");
}

// Two equal 2D steel discs (nu = 0.3: bonds and two-neighbour interactions) 0.2 mm apart meet
// head-on at 10 m/s each and separate; no damage.
const char* kImpact = R"(# SI units
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.3}
bodies:
  - {name: left, material: steel, dimension: 2, geometry: {type: sphere, center: [-0.0101, 0], radius: 0.01},
     spacing: 0.001, horizon_ratio: 3.015}
  - {name: right, material: steel, dimension: 2, geometry: {type: sphere, center: [0.0101, 0], radius: 0.01},
     spacing: 0.001, horizon_ratio: 3.015}
conditions:
  - {type: initial_velocity, body: left, value: [10, 0]}
  - {type: initial_velocity, body: right, value: [-10, 0]}
contact: {stiffness: 1.0e11, radius: 0.0008}
time: {end: 4.0e-5}
output: {history_interval: 10}
)";

// A pre-cracked strip torn apart; bonds only (nu = 1/3 in plane stress makes C2 = 0).
const char* kTear = R"(# SI units
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.3333333333333333, fracture_energy: 50}
bodies:
  - name: strip
    material: steel
    dimension: 2
    geometry: {type: box, min: [0, 0], max: [0.04, 0.02]}
    spacing: 0.001
    horizon_ratio: 3.015
    precracks: [[[0, 0.01], [0.015, 0.01]]]
conditions:
  - {type: velocity, body: strip, region: {type: box, min: [0, 0.018], max: [0.04, 0.02]},
     value: [0, 1], components: [y], ramp_time: 2.0e-6}
  - {type: velocity, body: strip, region: {type: box, min: [0, 0], max: [0.04, 0.002]},
     value: [0, -1], components: [y], ramp_time: 2.0e-6}
time: {end: 4.0e-5}
output: {history_interval: 20}
)";

}  // namespace

TEST_CASE("an elastic impact keeps the energy balance within 1 % of the initial kinetic energy",
          "[energy]") {
  const auto s = run_case("impact", kImpact);
  // Every point: area 1 mm^2, 7850 kg/m^2, 10 m/s.
  const double initial_kinetic = 0.5 * 7850 * s["points"].get<double>() * 1e-6 * 100;
  const auto& e = s["energy"];
  INFO(s.dump(1));
  CHECK(s["contact"]["point_pairs_in_contact_peak"].get<long long>() > 0);  // they did touch
  CHECK(e["kinetic"].get<double>() > 0.5 * initial_kinetic);                // and bounced apart
  CHECK(std::abs(e["balance_error"].get<double>()) < 0.01 * initial_kinetic);
}

TEST_CASE("with bonds breaking, the dissipated term accounts for the energy lost", "[energy]") {
  // Booked at the step's midpoint, the error of a failure is second order in dt: measured
  // 1.1 % of the dissipated energy at the default step and 21x less at half the step (booked at
  // the step's end: 20 %, halving with dt).
  const auto coarse = run_case("tear-coarse", kTear);
  const auto fine = run_case("tear-fine", kTear, "--set time.safety=0.4");
  const double dissipated = coarse["energy"]["dissipated"];
  const double error_coarse = std::abs(coarse["energy"]["balance_error"].get<double>());
  const double error_fine = std::abs(fine["energy"]["balance_error"].get<double>());
  INFO("dissipated " << dissipated << " J/m, balance error " << error_coarse << " (dt) and "
                     << error_fine << " (dt/2) J/m");
  REQUIRE(coarse["broken_bonds"].get<int>() > 1000);
  CHECK(dissipated > 0.3 * coarse["energy"]["external_work"].get<double>());
  CHECK(error_coarse < 0.03 * dissipated);
  CHECK(error_fine < 0.25 * error_coarse);  // at least second order
}
