// The contact speed bound on the time step and the tunnelling guard (src/engine/simulation.hpp):
// a 2000 m/s impact gets an automatic dt lowered to 0.25 l_c / closing speed and then runs
// without tripping the guard; a case dt above the bound is refused unless forced; forced, the
// guard stops the run at the first step with the body, point, step and time.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "run_helpers.hpp"

using namespace ckpd::testing;

namespace {

// A 2D steel disc at 2000 m/s, 0.1 mm from a plate, l_c = 0.2 mm: 0.25 l_c / 2000 m/s = 25 ns,
// below the stable-step estimate (about 80 ns).
const char* kFastImpact = R"(# SI units
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.3}
bodies:
  - {name: projectile, material: steel, dimension: 2, geometry: {type: sphere, center: [-0.0061, 0], radius: 0.006},
     spacing: 0.001, horizon_ratio: 3.015}
  - {name: target, material: steel, dimension: 2, geometry: {type: box, min: [0, -0.02], max: [0.01, 0.02]},
     spacing: 0.001, horizon_ratio: 3.015}
conditions:
  - {type: initial_velocity, body: projectile, value: [2000, 0]}
contact: {stiffness: 1.0e11, radius: 0.0002}
time: {end: 1.0e-6}
)";

struct Run {
  CommandResult result;
  nlohmann::json summary;  // null when the run wrote none
};

Run run_fast_impact(const std::string& tag, const std::string& extra) {
  const auto dir = fresh_dir(tag);
  const std::string file = write_file(dir / "case.yaml", kFastImpact);
  Run r;
  r.result = run_ckpd("run " + file + " --quiet --threads 1 --out " + (dir / "out").string() + " " +
                      extra);
  if (std::filesystem::exists(dir / "out" / "summary.json"))
    r.summary = read_json(dir / "out" / "summary.json");
  return r;
}

}  // namespace

TEST_CASE("a 2000 m/s impact gets its automatic dt lowered to the contact speed bound",
          "[contact_speed]") {
  const Run r = run_fast_impact("speed-auto", "");
  INFO(r.result.output);
  REQUIRE(r.result.exit_code == 0);
  const auto& s = r.summary;
  const auto& bound = s["dt_contact_speed_bound"];
  CHECK(bound["dt"].get<double>() == Approx(0.25 * 0.0002 / 2000).epsilon(1e-12));
  CHECK(bound["closing_speed"].get<double>() == Approx(2000));
  CHECK(bound["limits_dt"].get<bool>());
  CHECK(s["dt"].get<double>() == Approx(bound["dt"].get<double>()).epsilon(1e-12));
  CHECK(s["dt"].get<double>() < 0.8 * s["dt_estimate"].get<double>());  // it did lower it
  CHECK(s["status"] == "completed");  // the guard stayed quiet at this dt
  CHECK(s["contact"]["point_pairs_in_contact_peak"].get<long long>() > 0);  // and they met
}

TEST_CASE("a case dt above the contact speed bound is refused unless forced", "[contact_speed]") {
  // 60 ns: below the stable-step estimate, above the speed bound (25 ns).
  const Run r = run_fast_impact("speed-refused", "--set time.dt=6e-8");
  INFO(r.result.output);
  CHECK(r.result.exit_code != 0);
  CHECK(r.result.output.find("exceeds the contact speed bound") != std::string::npos);
  CHECK(r.result.output.find("allow_unstable_dt") != std::string::npos);
}

TEST_CASE("forced past the speed bound, the tunnelling guard stops the run and says where",
          "[contact_speed]") {
  // 2000 m/s x 60 ns = 0.12 mm per step, over half of l_c = 0.2 mm.
  const Run r =
      run_fast_impact("speed-forced", "--set time.dt=6e-8 --set time.allow_unstable_dt=true");
  INFO(r.result.output);
  CHECK(r.result.exit_code == 3);
  REQUIRE(r.summary.is_object());
  CHECK(r.summary["status"] == "tunnelling");
  const std::string message = r.summary["message"];
  CHECK(message.find("contact tunnelling at step 1, t = 6e-08 s") != std::string::npos);
  CHECK(message.find("body 'projectile', point") != std::string::npos);
  CHECK(message.find("0.5 x its smallest contact radius l_c = 0.0002 m") != std::string::npos);
}
