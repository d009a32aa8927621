// `far_field: {tolerance: T, corotated: B}` on a body (src/case/case_loader.cpp): T = 0 runs
// exactly as without the key (history.csv byte for byte); T > 0 adds the history column
// exact_fraction and summary.json's far_field entry; `ckpd check` reports the operator's memory;
// bad values and a model without a linearisation are refused naming file, line and key, exit 2.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "run_helpers.hpp"

using namespace ckpd::testing;

namespace {

// A small precracked 2D plate pulled apart; KEY is replaced by the body key under test.
const char* kCase = R"(# a small 2D plate, SI units
materials:
  steel: {density: 7580, youngs_modulus: 210e9, poisson_ratio: 0.3, fracture_energy: 140}
bodies:
  - name: plate
    material: steel
    dimension: 2
    plane: stress
    geometry: {type: box, min: [0, 0], max: [0.2, 0.2]}
    spacing: 0.005
    horizon_ratio: 3.015
    KEY
    precracks:
      - [[0, 0.1], [0.05, 0.1]]
conditions:
  - {type: velocity, body: plate, region: {type: box, min: [0, 0.19], max: [0.2, 0.2]},
     value: [0, 1], components: [y]}
time: {steps: 30}
output: {history_interval: 5}
)";

std::string with_key(const std::string& key) {
  std::string text = kCase;
  return text.replace(text.find("KEY"), 3, key.empty() ? "# no key" : key);
}

std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

CommandResult run_case(const std::string& text, const std::filesystem::path& dir,
                       const std::string& command = "run") {
  const std::string file = write_file(dir / "case.yaml", text);
  return run_ckpd(command + " " + file + " --quiet --out " + (dir / "out").string());
}

}  // namespace

TEST_CASE("far_field with tolerance 0 runs bit for bit as without the key", "[far_field]") {
  const auto a = fresh_dir("ff-none"), b = fresh_dir("ff-zero");
  const CommandResult none = run_case(with_key(""), a);
  const CommandResult zero = run_case(with_key("far_field: {tolerance: 0}"), b);
  INFO(none.output << zero.output);
  REQUIRE(none.exit_code == 0);
  REQUIRE(zero.exit_code == 0);
  const std::string h = read_text(a / "out" / "history.csv");
  CHECK(h.find("exact_fraction") == std::string::npos);
  CHECK(h == read_text(b / "out" / "history.csv"));
  CHECK_FALSE(read_json(b / "out" / "summary.json")["bodies"][0].contains("far_field"));
}

TEST_CASE("far_field reports the exact fraction in history.csv, summary.json and ckpd check",
          "[far_field]") {
  const auto dir = fresh_dir("ff-on");
  const std::string text = with_key("far_field: {tolerance: 1e-3}");
  const CommandResult r = run_case(text, dir);
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const std::string h = read_text(dir / "out" / "history.csv");
  CHECK(h.substr(0, h.find('\n')).ends_with(",exact_fraction"));
  const auto s = read_json(dir / "out" / "summary.json");
  const auto& ff = s["bodies"][0]["far_field"];
  CHECK(ff["tolerance"] == 1e-3);
  // The precrack's families are exact from the start, the far plate linear.
  CHECK(ff["exact_fraction"].get<double>() > 0);
  CHECK(ff["exact_fraction"].get<double>() < 1);
  CHECK(ff["operator_bytes"].get<double>() > 0);
  const CommandResult c = run_ckpd("check " + write_file(dir / "check.yaml", text) + " --steps 2");
  INFO(c.output);
  CHECK(c.exit_code == 0);
  CHECK(c.output.find("far field: tolerance 0.001, linear operator") != std::string::npos);
  CHECK(c.output.find("fraction of its points exact after the timed steps") != std::string::npos);
}

// The number after `key` in `text` (the first occurrence).
double number_after(const std::string& text, const std::string& key) {
  const std::size_t at = text.find(key);
  REQUIRE(at != std::string::npos);
  return std::stod(text.substr(at + key.size()));
}

TEST_CASE("check --cost-ratio measures the far field's cost ratio and prints the speed-up bound",
          "[far_field]") {
  const auto dir = fresh_dir("ff-cost");
  for (const char* key :
       {"far_field: {tolerance: 1e-3}", "far_field: {tolerance: 1e-3, corotated: true}"}) {
    INFO(key);
    const std::string file = write_file(dir / "check.yaml", with_key(key));
    const CommandResult c = run_ckpd("check " + file + " --steps 3 --cost-ratio");
    INFO(c.output);
    REQUIRE(c.exit_code == 0);
    const double linear = number_after(c.output, "over 3 steps each: ");
    const double f0 = number_after(c.output, "with the tolerance lifted (exact fraction ");
    const double exact = number_after(c.output, "only points near damage exact), ");
    const double ratio = number_after(c.output, "cost ratio c = ");
    // The precrack's families stay exact with the tolerance lifted; the rest is linear.
    CHECK(f0 > 0);
    CHECK(f0 < 0.5);
    CHECK(linear > 0);
    CHECK(exact > 0);
    // c with the probe's exact points taken out, and the bound at f = 0.5 from it (printed to
    // six digits).
    CHECK(ratio == Approx((linear / exact - f0) / (1 - f0)).epsilon(1e-4));
    const std::string bounds =
        c.output.substr(c.output.find("; ", c.output.find("measured there")));
    std::istringstream in(bounds.substr(2));
    double b1 = 0, b2 = 0, b3 = 0, b5 = 0;
    char x = 0, comma = 0;
    in >> b1 >> x >> comma >> b2 >> x >> comma >> b3 >> x >> comma >> b5;
    CHECK(b5 == Approx(1 / (0.5 + 0.5 * ratio)).epsilon(1e-4));
    CHECK(b1 == Approx(1 / (0.1 + 0.9 * ratio)).epsilon(1e-4));
  }
  // The probe stays within the case's 30 steps: 20 timed leave 5 of each kind, 30 none.
  const std::string file = write_file(dir / "few.yaml", with_key("far_field: {tolerance: 1e-3}"));
  const CommandResult five = run_ckpd("check " + file + " --steps 20 --cost-ratio");
  CHECK(five.exit_code == 0);
  CHECK(five.output.find("over 5 steps each") != std::string::npos);
  const CommandResult none_left = run_ckpd("check " + file + " --steps 30 --cost-ratio");
  CHECK(none_left.exit_code == 0);
  CHECK(none_left.output.find("plans too few steps for the probe (30 in all, 30 timed)") !=
        std::string::npos);
  // Without a far field the option says so.
  const CommandResult none =
      run_ckpd("check " + write_file(dir / "none.yaml", with_key("")) + " --steps 1 --cost-ratio");
  CHECK(none.exit_code == 0);
  CHECK(none.output.find("no body of this case has a far field") != std::string::npos);
}

TEST_CASE("a corotated far_field is reported as such and keeps the plate linear", "[far_field]") {
  const auto dir = fresh_dir("ff-corotated");
  const std::string text = with_key("far_field: {tolerance: 1e-3, corotated: true}");
  const CommandResult r = run_case(text, dir);
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto s = read_json(dir / "out" / "summary.json");
  const auto& ff = s["bodies"][0]["far_field"];
  CHECK(ff["corotated"] == true);
  CHECK(ff["exact_fraction"].get<double>() > 0);
  CHECK(ff["exact_fraction"].get<double>() < 1);
  const CommandResult c = run_ckpd("check " + write_file(dir / "check.yaml", text) + " --steps 0");
  INFO(c.output);
  CHECK(c.output.find("corotated (shape tensors and rotations") != std::string::npos);
}

TEST_CASE("a bad far_field is refused with file, line and key", "[far_field]") {
  struct Row {
    const char* key;
    const char* where;
    const char* says;
  };
  for (const Row& row :
       {Row{"far_field: {tolerance: -1e-3}", "bodies[0].far_field.tolerance", ""},
        Row{"far_field: {tolerance: small}", "bodies[0].far_field.tolerance", ""},
        Row{"far_field: 1e-3", "bodies[0].far_field", "{tolerance: T, corotated"},
        Row{"far_field: {tolerance: 1e-3, corotated: maybe}", "bodies[0].far_field.corotated", ""},
        Row{"far_field: {tolerance: 1e-3, tol: 2}", "tol", ""},
        Row{"far_field: {}", "tolerance", ""}}) {
    const auto dir = fresh_dir("ff-bad");
    const CommandResult r = run_case(with_key(row.key), dir);
    INFO(row.key << ": " << r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("case.yaml:12") != std::string::npos);
    CHECK(r.output.find(row.where) != std::string::npos);
    CHECK(r.output.find(row.says) != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir / "out" / "summary.json"));
  }
}

TEST_CASE("far_field on a state-based body is refused: it has no linearisation", "[far_field]") {
  const auto dir = fresh_dir("ff-sb");
  std::string text = with_key("far_field: {tolerance: 1e-3}");
  const std::string material = "steel: {density";
  text.replace(text.find(material), material.size(), "steel: {model: state_based, density");
  const CommandResult r = run_case(text, dir);
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("case.yaml:12") != std::string::npos);
  CHECK(r.output.find("bodies[0].far_field") != std::string::npos);
  CHECK(r.output.find("linearisation") != std::string::npos);
}

TEST_CASE("summary.json counts the sets each kernel evaluated: fewer with the far field",
          "[far_field]") {
  const auto a = fresh_dir("ff-count-exact"), b = fresh_dir("ff-count-zero"),
             c = fresh_dir("ff-count-on");
  REQUIRE(run_case(with_key(""), a).exit_code == 0);
  REQUIRE(run_case(with_key("far_field: {tolerance: 0}"), b).exit_code == 0);
  REQUIRE(run_case(with_key("far_field: {tolerance: 1e-3}"), c).exit_code == 0);
  const auto exact = read_json(a / "out" / "summary.json")["bodies"][0]["evaluated"];
  const auto zero = read_json(b / "out" / "summary.json")["bodies"][0]["evaluated"];
  const auto on = read_json(c / "out" / "summary.json")["bodies"][0]["evaluated"];
  INFO(exact.dump() << " " << zero.dump() << " " << on.dump());
  CHECK(exact == zero);
  // 2D: bonds and triangles; the plate's 31 evaluations (the start and 30 steps) each hold at
  // least one evaluation of its intact bonds.
  CHECK(exact["tetrahedra"] == 0);
  CHECK(exact["bonds"].get<double>() > 31 * 1000.0);
  CHECK(exact["triangles"].get<double>() > exact["bonds"].get<double>());
  // The linear points' sets are left out: less work, not more.
  CHECK(on["bonds"].get<double>() < exact["bonds"].get<double>());
  CHECK(on["triangles"].get<double>() < exact["triangles"].get<double>());
  CHECK(on["triangles"].get<double>() > 0);  // the precrack's families stay exact
}
