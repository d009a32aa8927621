// Set-up warnings (src/engine/scene_warnings.hpp): `ckpd check` and a run's set-up lines say
// when a valid scene probably does not do what its author meant, and the exit status stays 0.
#include <catch2/catch.hpp>
#include <fstream>
#include <sstream>
#include <string>

#include "run_helpers.hpp"

using namespace ckpd::testing;

namespace {

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

std::string material(const std::string& extra = "", double nu = 0.25) {
  std::ostringstream s;
  s << "materials:\n  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: " << nu << extra
    << "}\n";
  return s.str();
}

// Two small cubes 2 mm apart, the left one moving at 50 m/s towards the right one.
std::string closing_cubes(const std::string& contact) {
  return material() +
         "bodies:\n"
         "  - {name: left, material: steel, geometry: {type: box, min: [-0.006, 0, 0], max: "
         "[-0.002, 0.004, 0.004]}, spacing: 0.001, horizon_ratio: 2.015}\n"
         "  - {name: right, material: steel, geometry: {type: box, min: [0, 0, 0], max: [0.004, "
         "0.004, 0.004]}, spacing: 0.001, horizon_ratio: 2.015}\n"
         "conditions:\n  - {type: initial_velocity, body: left, value: [50, 0, 0]}\n" +
         contact + "time: {end: 1.0e-4}\n";
}

CommandResult check(const std::string& tag, const std::string& text, const std::string& args = "") {
  const auto dir = fresh_dir(tag);
  return run_ckpd("check " + write_file(dir / "case.yaml", text) + " --steps 1 " + args);
}

}  // namespace

TEST_CASE("check warns about bodies closing on each other without contact", "[cli][warnings]") {
  const CommandResult none = check("closing", closing_cubes(""));
  INFO(none.output);
  CHECK(none.exit_code == 0);
  CHECK(has(none.output, "warning: bodies 'left' and 'right' close on each other"));
  CHECK(has(none.output, "no `contact` section"));

  const CommandResult with =
      check("closing-contact", closing_cubes("contact: {stiffness: 1e12}\n"));
  INFO(with.output);
  CHECK(with.exit_code == 0);
  CHECK_FALSE(has(with.output, "close on each other"));

  // Moving apart: nothing to say.
  std::string apart = closing_cubes("");
  apart.replace(apart.find("[50, 0, 0]"), 10, "[-50, 0, 0]");
  CHECK_FALSE(has(check("apart", apart).output, "close on each other"));
}

TEST_CASE("check warns that the seed's own-horizon contact rule does not conserve",
          "[cli][warnings]") {
  const CommandResult seed = check(
      "own-horizon", closing_cubes("contact: {stiffness: 1e12, law: repulsive_own_horizon}\n"));
  INFO(seed.output);
  CHECK(seed.exit_code == 0);
  CHECK(has(seed.output, "repulsive_own_horizon"));
  CHECK(has(seed.output, "does not conserve momentum or energy"));
  CHECK_FALSE(has(check("default-law", closing_cubes("contact: {stiffness: 1e12}\n")).output,
                  "does not conserve"));
}

TEST_CASE("check on the sphere-disc case with the seed's rule prints the warning",
          "[cli][warnings]") {
  // The seed's scene made small enough to set up in a moment: a 60 mm disc of horizon 15 mm
  // (still not the sphere's 12.06 mm).
  const CommandResult r =
      run_ckpd("check " + std::string(CKPD_SOURCE_DIR) +
               "/cases/sphere_disc_impact.yaml --steps 0 --set contact.law=repulsive_own_horizon "
               "--set bodies.disc.geometry.radius=0.03 --set bodies.disc.horizon=0.015");
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(has(r.output, "warning: contact 'sphere'/'disc' uses `repulsive_own_horizon`"));
  CHECK(has(r.output, "does not conserve momentum or energy"));
}

TEST_CASE("check warns about damage asked of bodies that cannot break", "[cli][warnings]") {
  const std::string cube =
      "bodies:\n  - {name: cube, material: steel, geometry: {type: box, min: [0, 0, 0], max: "
      "[0.004, 0.004, 0.004]}, spacing: 0.001, horizon_ratio: 2.015}\n"
      "time: {steps: 10}\noutput: {fields: [damage], field_interval: 5}\n";
  const CommandResult r = check("no-gc", material() + cube);
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(has(r.output, "warning: the case writes the damage field, but no body can break"));
  CHECK_FALSE(has(check("gc", material(", fracture_energy: 1000") + cube).output, "can break"));
  // Pre-cracks on a body without fracture_energy: they cannot grow.
  std::string cracked = cube;
  cracked.replace(cracked.find("horizon_ratio: 2.015}"), 21,
                  "horizon_ratio: 2.015, precracks: [[[0.002, -1, -1], [0.002, 1, -1], [0.002, "
                  "1, 1], [0.002, -1, 1]]]}");
  const CommandResult p = check("precrack-no-gc", material() + cracked);
  INFO(p.output);
  CHECK(has(p.output, "warning: body 'cube' has pre-cracks"));
  CHECK(has(p.output, "cannot break further"));
}

TEST_CASE("check warns about the cost of three-neighbour interactions and a negative C3",
          "[cli][warnings]") {
  const std::string cube =
      "bodies:\n  - {name: cube, material: steel, geometry: {type: box, min: [0, 0, 0], max: "
      "[0.004, 0.004, 0.004]}, spacing: 0.001, horizon_ratio: 2.015}\ntime: {steps: 10}\n";
  const CommandResult high = check("nu-0.3", material("", 0.3) + cube);
  INFO(high.output);
  CHECK(has(high.output, "warning: body 'cube': a Poisson ratio other than 1/4"));
  CHECK(has(high.output, "10-40 times"));
  CHECK_FALSE(has(high.output, "C3 < 0"));
  const CommandResult low = check("nu-0.2", material("", 0.2) + cube);
  INFO(low.output);
  CHECK(has(low.output, "C3 < 0"));
  CHECK_FALSE(has(check("nu-0.25", material() + cube).output, "Poisson ratio other than"));
}

TEST_CASE("a run repeats the set-up warnings on screen and in run.log", "[cli][warnings]") {
  const auto dir = fresh_dir("warn-run");
  const std::string file = write_file(dir / "case.yaml", closing_cubes(""));
  const CommandResult r = run_ckpd("run " + file + " --out " + (dir / "out").string());
  INFO(r.output);
  CHECK(r.exit_code == 0);
  CHECK(has(r.output, "warning: bodies 'left' and 'right' close on each other"));
  std::ifstream log(dir / "out" / "run.log");
  const std::string text((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>());
  CHECK(has(text, "warning: bodies 'left' and 'right' close on each other"));
  const CommandResult quiet =
      run_ckpd("run " + file + " --quiet --out " + (dir / "quiet").string());
  CHECK(quiet.exit_code == 0);
  CHECK(has(quiet.output, "ckpd: warning: bodies 'left' and 'right'"));
}
