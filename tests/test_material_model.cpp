// A material's `model` key (src/case/material_model.hpp): ckpd by default, an unknown model is
// refused listing the known ones, and each model rejects keys it does not read, naming file,
// line and key.
#include <catch2/catch.hpp>
#include <filesystem>

#include "run_helpers.hpp"

using namespace ckpd::testing;

namespace {

const char* kCase = R"(# a small 2D plate, SI units
materials:
  steel: {MODEL density: 7580, youngs_modulus: 210e9, poisson_ratio: 0.3, critical_stretch: 0.01}
bodies:
  - name: plate
    material: steel
    dimension: 2
    geometry: {type: box, min: [0, 0], max: [0.05, 0.05]}
    spacing: 0.005
    horizon_ratio: 3.015
time: {steps: 5}
)";

std::string with_model(const std::string& model_key) {
  std::string text = kCase;
  return text.replace(text.find("MODEL "), 6, model_key);
}

CommandResult run_case(const std::string& text, const std::filesystem::path& dir) {
  const std::string file = write_file(dir / "case.yaml", text);
  return run_ckpd("run " + file + " --quiet --out " + (dir / "out").string());
}

}  // namespace

TEST_CASE("a material without a model key is a CKPD material", "[material_model]") {
  const auto a = fresh_dir("model-default"), b = fresh_dir("model-ckpd");
  const CommandResult plain = run_case(with_model(""), a);
  const CommandResult named = run_case(with_model("model: ckpd, "), b);
  INFO(plain.output << named.output);
  REQUIRE(plain.exit_code == 0);
  REQUIRE(named.exit_code == 0);
  const auto s1 = read_json(a / "out" / "summary.json"), s2 = read_json(b / "out" / "summary.json");
  CHECK(s1["bodies"][0]["kernel"]["model"] == "ckpd");
  CHECK(s1["energy"] == s2["energy"]);
}

TEST_CASE("an unknown force model is refused with file, line and the known models",
          "[material_model]") {
  const auto dir = fresh_dir("model-unknown");
  const CommandResult r = run_case(with_model("model: bogus, "), dir);
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("case.yaml:3") != std::string::npos);
  CHECK(r.output.find("materials.steel.model") != std::string::npos);
  CHECK(r.output.find("ckpd") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir / "out" / "summary.json"));
}

TEST_CASE("a CKPD material rejects a key it does not read", "[material_model]") {
  const auto dir = fresh_dir("model-key");
  const CommandResult r = run_case(with_model("micromodulus: 1e20, "), dir);
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("materials.steel.micromodulus") != std::string::npos);
  CHECK(r.output.find("unknown key") != std::string::npos);
}
