// Bad contact and rigid-body input: a clear error naming the file, line and key, exit status 2,
// and no summary.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>

#include "run_helpers.hpp"

using namespace ckpd::testing;

namespace {

// A steel ball over a free rigid block, with contact; lines numbered for the checks below.
const char* kGoodCase = R"(# a ball and a rigid block, SI units
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.25}
bodies:
  - {name: ball, material: steel, geometry: {type: sphere, center: [0, 0, 0.004], radius: 0.0025},
     spacing: 0.001, horizon_ratio: 2.015}
  - name: block
    rigid: {motion: free, mass: 0.01}
    geometry: {type: box, min: [-0.004, -0.004, -0.002], max: [0.004, 0.004, 0]}
    spacing: 0.001
contact:
  stiffness: 1.0e12
  radius: 0.0008
  pairs:
    - {bodies: [ball, block], skin: 0.0005}
time: {steps: 5}
)";

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

void expect_rejected(const std::string& case_text, std::initializer_list<std::string> fragments) {
  const auto dir = fresh_dir("bad-contact");
  const std::string file = write_file(dir / "case.yaml", case_text);
  const CommandResult r = run_ckpd("run " + file + " --out " + (dir / "out").string());
  INFO(r.output);
  CHECK(r.exit_code == 2);
  for (const std::string& f : fragments) CHECK(r.output.find(f) != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir / "out" / "summary.json"));
}

}  // namespace

TEST_CASE("the good contact case runs, so the rejections below are about their one change",
          "[cli][contact]") {
  const auto dir = fresh_dir("good-contact");
  const std::string file = write_file(dir / "case.yaml", kGoodCase);
  const CommandResult r = run_ckpd("run " + file + " --quiet --out " + (dir / "out").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto summary = read_json(dir / "out" / "summary.json");
  CHECK(summary["contact"]["active"] == true);
  CHECK(summary["contact"]["rigid_bodies"][0]["motion"] == "free");
}

TEST_CASE("a contact pair naming a body that does not exist is rejected", "[cli][contact]") {
  expect_rejected(replace(kGoodCase, "{bodies: [ball, block]", "{bodies: [ball, blok]"),
                  {"case.yaml:15: contact.pairs[0].bodies[1]", "name of a body", "'blok'"});
}

TEST_CASE("a negative contact radius or stiffness is rejected", "[cli][contact]") {
  expect_rejected(replace(kGoodCase, "radius: 0.0008", "radius: -0.0008"),
                  {"case.yaml:13: contact.radius", "positive", "'-0.0008'"});
  expect_rejected(replace(kGoodCase, "stiffness: 1.0e12", "stiffness: -1.0e12"),
                  {"case.yaml:12: contact.stiffness", "positive"});
  expect_rejected(replace(kGoodCase, "skin: 0.0005}", "skin: 0.0005, stiffness: -5}"),
                  {"case.yaml:15: contact.pairs[0].stiffness", "positive"});
}

TEST_CASE("a free rigid body without a mass is rejected", "[cli][contact]") {
  expect_rejected(replace(kGoodCase, "rigid: {motion: free, mass: 0.01}", "rigid: {motion: free}"),
                  {"case.yaml:8: bodies[1].rigid", "a mass for a free rigid body"});
  expect_rejected(replace(kGoodCase, "mass: 0.01", "mass: 0"),
                  {"case.yaml:8: bodies[1].rigid.mass", "positive"});
}

TEST_CASE("unknown contact and rigid keys are errors", "[cli][contact]") {
  expect_rejected(replace(kGoodCase, "  radius: 0.0008", "  radius: 0.0008\n  skn: 0.001"),
                  {"case.yaml:14: contact.skn", "unknown key"});
  expect_rejected(replace(kGoodCase, "mass: 0.01}", "mass: 0.01, velocty: [0, 0, 1]}"),
                  {"bodies[1].rigid.velocty", "unknown key"});
}

TEST_CASE("rigid bodies refuse what only bonded bodies have, and motion conditions",
          "[cli][contact]") {
  expect_rejected(replace(kGoodCase, "    spacing: 0.001\ncontact",
                          "    spacing: 0.001\n"
                          "    horizon_ratio: 3\ncontact"),
                  {"bodies[1].horizon_ratio", "no `horizon_ratio` on a rigid body"});
  std::string text = kGoodCase;
  text += "conditions:\n  - {type: initial_velocity, body: block, value: [0, 0, 1]}\n";
  expect_rejected(text, {"conditions[0].type", "its motion is set by `rigid`"});
}

TEST_CASE("two rigid bodies in contact need a horizon", "[cli][contact]") {
  const std::string text = replace(
      kGoodCase,
      "  - {name: ball, material: steel, geometry: {type: sphere, center: [0, 0, 0.004], radius: "
      "0.0025},\n     spacing: 0.001, horizon_ratio: 2.015}",
      "  - {name: ball, material: steel, rigid: {motion: free}, geometry: {type: sphere, center: "
      "[0, 0, 0.004], radius: 0.0025},\n     spacing: 0.001}");
  expect_rejected(text, {"contact.pairs[0]", "needs a horizon"});
  // With one it runs.
  const auto dir = fresh_dir("rigid-pair");
  const std::string file = write_file(
      dir / "case.yaml", replace(text, "skin: 0.0005}", "skin: 0.0005, horizon: 0.002}"));
  const CommandResult r = run_ckpd("run " + file + " --quiet --out " + (dir / "out").string());
  INFO(r.output);
  CHECK(r.exit_code == 0);
}

TEST_CASE("an unknown contact law is rejected with the known ones listed", "[cli][contact][dem]") {
  expect_rejected(replace(kGoodCase, "  radius: 0.0008", "  radius: 0.0008\n  law: hooke"),
                  {"case.yaml:14: contact.law", "a contact law: one of", "hertz_mindlin",
                   "linear_dashpot", "repulsive", "'hooke'"});
}

TEST_CASE("a contact law's parameters are checked: 0 < e <= 1, mu >= 0, none missing",
          "[cli][contact][dem]") {
  const std::string dashpot = "{bodies: [ball, block], skin: 0.0005, law: linear_dashpot, ";
  expect_rejected(
      replace(kGoodCase, "{bodies: [ball, block], skin: 0.0005}", dashpot + "restitution: 1.5}"),
      {"case.yaml:15: contact.pairs[0].restitution", "restitution e in (0, 1]", "'1.5'"});
  expect_rejected(
      replace(kGoodCase, "{bodies: [ball, block], skin: 0.0005}", dashpot + "restitution: 0}"),
      {"case.yaml:15: contact.pairs[0].restitution", "(0, 1]"});
  expect_rejected(replace(kGoodCase, "{bodies: [ball, block], skin: 0.0005}",
                          dashpot + "restitution: 0.5, friction: -0.2}"),
                  {"case.yaml:15: contact.pairs[0].friction", "mu >= 0", "'-0.2'"});
  expect_rejected(
      replace(kGoodCase, "{bodies: [ball, block], skin: 0.0005}", dashpot + "friction: 0.2}"),
      {"case.yaml:15: contact.pairs[0]", "`restitution` for contact law `linear_dashpot`"});
  expect_rejected(
      replace(kGoodCase, "{bodies: [ball, block], skin: 0.0005}",
              "{bodies: [ball, block], law: hertz_mindlin, restitution: 0.5, poisson_ratio: 0.3}"),
      {"case.yaml:15: contact.pairs[0]", "hertz_mindlin", "of body 'block', a rigid body",
       "`youngs_modulus` and `poisson_ratio` in its `rigid` section"});
  // A parameter of another law than the one in effect.
  expect_rejected(replace(kGoodCase, "{bodies: [ball, block], skin: 0.0005}",
                          "{bodies: [ball, block], skin: 0.0005, friction: 0.3}"),
                  {"case.yaml:15: contact.pairs[0].friction", "parameter of contact law",
                   "the law here is `repulsive`"});
}

TEST_CASE("a case with contact laws and friction runs and reports them", "[cli][contact][dem]") {
  const auto dir = fresh_dir("dem-contact");
  const std::string file = write_file(
      dir / "case.yaml",
      replace(kGoodCase, "{bodies: [ball, block], skin: 0.0005}",
              "{bodies: [ball, block], skin: 0.0005, law: linear_dashpot, restitution: 0.5, "
              "friction: 0.3}"));
  const CommandResult r = run_ckpd("run " + file + " --out " + (dir / "out").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("contact ball/block: law linear_dashpot, friction 0.3, normal damping "
                      "ratio 0.21") != std::string::npos);
  const auto summary = read_json(dir / "out" / "summary.json");
  CHECK(summary["contact"]["laws"][0]["law"] == "linear_dashpot");
  CHECK(summary["contact"]["laws"][0]["damping_ratio"].get<double>() ==
        Approx(-std::log(0.5) / std::sqrt(M_PI * M_PI + std::log(0.5) * std::log(0.5))));
}

TEST_CASE("hertz_mindlin reads E and nu of a rigid body from its rigid section",
          "[cli][contact][dem]") {
  const std::string hertz =
      replace(kGoodCase, "{bodies: [ball, block], skin: 0.0005}",
              "{bodies: [ball, block], skin: 0.0005, law: hertz_mindlin, restitution: 0.5}");
  // Bad values and a second source are refused with the key.
  expect_rejected(replace(hertz, "rigid: {motion: free, mass: 0.01}",
                          "rigid: {motion: free, mass: 0.01, youngs_modulus: 200e9, "
                          "poisson_ratio: 0.7}"),
                  {"case.yaml:8: bodies[1].rigid.poisson_ratio", "Poisson's ratio in (-1, 0.5)"});
  expect_rejected(replace(hertz, "rigid: {motion: free, mass: 0.01}",
                          "rigid: {motion: free, mass: 0.01, youngs_modulus: 200e9}"),
                  {"case.yaml:8: bodies[1].rigid", "poisson_ratio"});
  expect_rejected(replace(hertz, "rigid: {motion: free, mass: 0.01}",
                          "rigid: {motion: free, youngs_modulus: 200e9, poisson_ratio: 0.3}\n"
                          "    material: steel"),
                  {"bodies[1].rigid.youngs_modulus", "or a material (its E and nu), not both"});
  // A deformable body whose material has no E and nu (pmb) needs them in the contact section.
  std::string pmb =
      replace(hertz, "  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.25}",
              "  steel: {model: pmb, density: 7850, micromodulus: 1.0e20}");
  pmb = replace(pmb, "rigid: {motion: free, mass: 0.01}",
                "rigid: {motion: free, mass: 0.01, youngs_modulus: 200e9, poisson_ratio: 0.3}");
  expect_rejected(
      pmb, {"case.yaml:15: contact.pairs[0]", "of body 'ball': its material's model has none",
            "for the pair in `contact`"});
  // With both keys the case runs.
  const auto dir = fresh_dir("hertz-rigid");
  const std::string file = write_file(
      dir / "case.yaml", replace(hertz, "rigid: {motion: free, mass: 0.01}",
                                 "rigid: {motion: free, mass: 0.01, youngs_modulus: 200e9, "
                                 "poisson_ratio: 0.3}"));
  const CommandResult r = run_ckpd("run " + file + " --quiet --out " + (dir / "out").string());
  INFO(r.output);
  CHECK(r.exit_code == 0);
}
