// A DEM sphere's case errors are refused before any work with exit 2 and a message naming the
// file, line and key: a negative or missing radius, a sphere given a geometry (or mesh wall,
// spacing) as well, a free sphere without a mass. A valid sphere case without `materials` runs.
#include <catch2/catch.hpp>

#include "run_helpers.hpp"

using namespace ckpd::testing;

namespace {

// Line 3 holds the sphere's `dem_sphere` (or what replaces it).
std::string sphere_case(const std::string& rigid, const std::string& sphere_line) {
  return "bodies:\n"
         "  - name: ball\n" +
         sphere_line + "    rigid: " + rigid +
         "\n"
         "  - {name: floor, rigid: {motion: prescribed, youngs_modulus: 70e9, poisson_ratio: "
         "0.25}, geometry: {type: box, min: [-0.01, -0.01, -0.002], max: [0.01, 0.01, 0]}, "
         "spacing: 0.001}\n"
         "contact: {law: hertz_mindlin, restitution: 0.9, friction: 0.3}\n"
         "time: {steps: 3}\n";
}

const std::string kRigid =
    "{motion: free, velocity: [0, 0, -1], density: 2500, youngs_modulus: 70e9, poisson_ratio: "
    "0.25}";

void expect_refused(const std::string& text, std::initializer_list<std::string> fragments) {
  const auto dir = fresh_dir("dem-errors");
  const std::string file = write_file(dir / "case.yaml", text);
  for (const std::string command : {"run ", "check "}) {
    const CommandResult r =
        run_ckpd(command + file +
                 (command == "run " ? " --quiet --out " + (dir / "out").string() : std::string()));
    INFO(command << "\n" << text << "\n" << r.output);
    CHECK(r.exit_code == 2);
    for (const std::string& f : fragments) CHECK(r.output.find(f) != std::string::npos);
  }
  CHECK_FALSE(std::filesystem::exists(dir / "out" / "summary.json"));
}

}  // namespace

TEST_CASE("a DEM sphere case without materials runs, so each refusal below is its one change",
          "[dem][dem_sphere]") {
  const auto dir = fresh_dir("dem-good");
  const std::string file =
      write_file(dir / "case.yaml",
                 sphere_case(kRigid, "    dem_sphere: {center: [0, 0, 0.00551], radius: 0.005}\n"));
  const CommandResult r = run_ckpd("run " + file + " --quiet --out " + (dir / "out").string());
  INFO(r.output);
  CHECK(r.exit_code == 0);
}

TEST_CASE("a DEM sphere with a negative or missing radius is refused naming the line and key",
          "[dem][dem_sphere]") {
  expect_refused(sphere_case(kRigid, "    dem_sphere: {center: [0, 0, 0.006], radius: -0.005}\n"),
                 {"case.yaml:3:", "dem_sphere.radius"});
  expect_refused(sphere_case(kRigid, "    dem_sphere: {center: [0, 0, 0.006], radius: 0}\n"),
                 {"case.yaml:3:", "dem_sphere.radius"});
  expect_refused(sphere_case(kRigid, "    dem_sphere: {center: [0, 0, 0.006]}\n"),
                 {"case.yaml:3:", "dem_sphere", "radius"});
}

TEST_CASE("a DEM sphere given a geometry, mesh wall or spacing as well is refused",
          "[dem][dem_sphere]") {
  const std::string sphere = "    dem_sphere: {center: [0, 0, 0.006], radius: 0.005}\n";
  expect_refused(sphere_case(kRigid, sphere + "    geometry: {type: sphere, center: [0, 0, 0.006], "
                                              "radius: 0.005}\n"),
                 {"case.yaml:4:", "geometry", "dem_sphere"});
  expect_refused(sphere_case(kRigid, sphere + "    spacing: 0.001\n"),
                 {"case.yaml:4:", "spacing", "dem_sphere"});
}

TEST_CASE("a free DEM sphere without a mass or density is refused naming its rigid section",
          "[dem][dem_sphere]") {
  expect_refused(
      sphere_case("{motion: free, velocity: [0, 0, -1], youngs_modulus: 70e9, poisson_ratio: 0.25}",
                  "    dem_sphere: {center: [0, 0, 0.006], radius: 0.005}\n"),
      {"case.yaml:4:", "rigid", "density"});
}
