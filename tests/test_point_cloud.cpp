// Bodies given as point clouds (`points: {file, format: csv}`): a lattice written as a cloud is
// the same body as the lattice-sampled box; every bad file is an error naming the file, the
// line and what was expected; a family fuller than the reference is an error unless the case
// says `beta: capped`, and then the cap is reported.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "run_helpers.hpp"
#include "src/case/case_loader.hpp"

using namespace ckpd;
using namespace ckpd::testing;

namespace {

constexpr double kDx = 0.005;  // m
constexpr int kSide = 10;      // points per edge

// A 2D case whose body reads `points.csv` next to it; `extra` adds keys to the body.
std::string cloud_case(const std::string& file = "points.csv", const std::string& extra = "") {
  return R"(# SI units
materials:
  steel: {density: 7580, youngs_modulus: 210e9, poisson_ratio: 0.3, fracture_energy: 140}
bodies:
  - name: plate
    material: steel
    dimension: 2
    points: {file: )" +
         file + R"(, format: csv}
    spacing: 0.005
    horizon_ratio: 3.015
)" + extra +
         R"(time: {steps: 5}
)";
}

// The cell centres of a kSide x kSide square lattice of spacing kDx scaled by `scale`, with
// volumes (scale kDx)^2: a regular cloud (scale 1) or a uniformly denser one (scale < 1).
std::string lattice_csv(double scale = 1.0, bool with_z = false) {
  std::ostringstream csv;
  csv.precision(17);
  csv << "# a comment line before the header\n" << (with_z ? "x,y,z,volume\n" : "x,y,volume\n");
  const double d = scale * kDx;
  for (int j = 0; j < kSide; ++j)
    for (int i = 0; i < kSide; ++i) {
      csv << (i + 0.5) * d << ", " << (j + 0.5) * d;
      if (with_z) csv << ", 0";
      csv << ", " << d * d << '\n';
    }
  return csv.str();
}

// Loads a case written with `csv` as points.csv and expects a CaseError holding every fragment.
void expect_error(const std::string& csv, std::initializer_list<std::string> fragments,
                  const std::string& case_text = cloud_case()) {
  const auto dir = fresh_dir("cloud-bad");
  write_file(dir / "points.csv", csv);
  const std::string file = write_file(dir / "case.yaml", case_text);
  try {
    load_scene(file);
    FAIL("the case loaded");
  } catch (const CaseError& e) {
    const std::string message = e.what();
    INFO(message);
    for (const std::string& f : fragments) CHECK(message.find(f) != std::string::npos);
  }
}

std::string with_line(const std::string& csv, int line, const std::string& text) {
  std::istringstream in(csv);
  std::ostringstream out;
  std::string l;
  for (int n = 1; std::getline(in, l); ++n) out << (n == line ? text : l) << '\n';
  return out.str();
}

}  // namespace

TEST_CASE("a lattice given as a point cloud is the same body as the sampled box", "[cloud]") {
  const auto dir = fresh_dir("cloud-lattice");
  write_file(dir / "points.csv", lattice_csv());
  const Scene cloud = load_scene(write_file(dir / "case.yaml", cloud_case()));
  const std::string box = "geometry: {type: box, min: [0, 0], max: [0.05, 0.05]}";
  std::string box_case = cloud_case();
  box_case.replace(box_case.find("points: {file: points.csv, format: csv}"),
                   std::string("points: {file: points.csv, format: csv}").size(), box);
  const Scene lattice = load_scene(write_file(dir / "box.yaml", box_case));
  const Body& a = cloud.bodies[0].body;
  const Body& b = lattice.bodies[0].body;
  REQUIRE(a.size() == b.size());
  CHECK(a.bond_count() == b.bond_count());
  CHECK(a.total_two_neighbour() == b.total_two_neighbour());
  for (std::size_t i = 0; i < a.size(); ++i) {
    CHECK((a.reference_position[i] - b.reference_position[i]).norm() < 1e-12);
    CHECK(a.beta[i] == Approx(b.beta[i]).epsilon(1e-12));
  }
  CHECK(a.beta_max_raw == Approx(1.0));
  CHECK(a.beta_capped_points == 0);
}

TEST_CASE("a 2D cloud may carry a z column of zeros; the path is relative to the case file",
          "[cloud]") {
  const auto dir = fresh_dir("cloud-z");
  std::filesystem::create_directories(dir / "data");
  write_file(dir / "data" / "points.csv", lattice_csv(1.0, true));
  const Scene s = load_scene(write_file(dir / "case.yaml", cloud_case("data/points.csv")));
  CHECK(s.bodies[0].body.size() == kSide * kSide);
}

TEST_CASE("bad point-cloud files are errors naming the file, the line and what was expected",
          "[cloud]") {
  const std::string good = lattice_csv();  // line 1 comment, line 2 header, points from line 3
  SECTION("missing file") {
    expect_error(good, {"case.yaml:8", "bodies[0].points.file", "nope.csv", "not a readable file"},
                 cloud_case("nope.csv"));
  }
  SECTION("wrong column count") {
    expect_error(with_line(good, 5, "0.1, 0.2"),
                 {"points.csv:5:", "3 comma-separated values (x,y,volume)", "got 2"});
  }
  SECTION("not a number") {
    expect_error(with_line(good, 4, "0.1, abc, 1e-5"),
                 {"points.csv:4:", "a finite number in column 'y'", "'abc'"});
    expect_error(with_line(good, 4, "0.1, 0.2, nan"), {"points.csv:4:", "column 'volume'"});
    expect_error(with_line(good, 4, "0.1, 0.2x, 1e-5"), {"points.csv:4:", "'0.2x'"});
  }
  SECTION("non-positive volume") {
    expect_error(with_line(good, 7, "0.1, 0.2, 0"), {"points.csv:7:", "a positive volume"});
    expect_error(with_line(good, 7, "0.1, 0.2, -1e-5"), {"points.csv:7:", "a positive volume"});
  }
  SECTION("2D point off the plane") {
    expect_error(with_line(lattice_csv(1.0, true), 6, "0.1, 0.2, 0.001, 2.5e-5"),
                 {"points.csv:6:", "z = 0 for a point of a 2D body", "0.001"});
  }
  SECTION("bad or missing header") {
    expect_error(with_line(good, 2, "x,y,vol"), {"points.csv:2:", "a header line 'x,y,volume'"});
    expect_error(with_line(good, 2, "0.1, 0.2, 2.5e-5"), {"points.csv:2:", "a header line"});
    std::string three_d = cloud_case();
    three_d.replace(three_d.find("dimension: 2"), 12, "dimension: 3");
    expect_error(good, {"points.csv:2:", "'x,y,z,volume' (a 3D body needs z)"}, three_d);
  }
  SECTION("empty file or no points") {
    expect_error("", {"points.csv", "empty file"});
    expect_error("x,y,volume\n", {"points.csv:1:", "points after the header"});
  }
  SECTION("coincident points") {
    expect_error(with_line(good, 8, "0.0025, 0.0025, 2.5e-5"),
                 {"points.csv:8:", "distinct points", "line 3"});
  }
  SECTION("more points than max_points") {
    expect_error(good, {"points.csv:", "at most 50 points"},
                 cloud_case("points.csv", "    max_points: 50\n"));
  }
  SECTION("unknown format, both geometry and points, neither") {
    std::string c = cloud_case();
    expect_error(good, {"points.format", "csv"},
                 c.replace(c.find("format: csv"), 11, "format: hdf5"));
    c = cloud_case("points.csv", "    geometry: {type: box, min: [0, 0], max: [0.05, 0.05]}\n");
    expect_error(good, {"either geometry or points"}, c);
    c = cloud_case();
    const std::string points_line = "    points: {file: points.csv, format: csv}\n";
    c.replace(c.find(points_line), points_line.size(), "");
    expect_error(good, {"a geometry (a shape) or points"}, c);
  }
}

TEST_CASE(
    "a family fuller than the reference is an error unless beta is capped, and the cap is "
    "reported",
    "[cloud]") {
  // A lattice 0.95 times the nominal spacing, volumes to match: an interior family holds 36
  // points of 0.9025 dx^2 instead of 28 of dx^2 (raw beta about 1.16).
  const std::string dense = lattice_csv(0.95);
  expect_error(dense, {"bodies[0]", "times the full family volume", "beta: capped"});
  expect_error(dense, {"bodies[0].beta", "'strict' or 'capped'"},
               cloud_case("points.csv", "    beta: sometimes\n"));

  const auto dir = fresh_dir("cloud-capped");
  write_file(dir / "points.csv", dense);
  const std::string file =
      write_file(dir / "case.yaml", cloud_case("points.csv", "    beta: capped\n"));
  const Scene s = load_scene(file);
  const Body& b = s.bodies[0].body;
  CHECK(b.beta_cap);
  CHECK(b.beta_capped_points > 0);
  CHECK(b.beta_capped_points < b.size());  // corners and edges stay below 1
  CHECK(b.beta_max_raw > 1.1);
  for (double beta : b.beta) CHECK(beta <= 1.0);

  // The run prints the cap and summary.json records it.
  const CommandResult r = run_ckpd("run " + file + " --out " + (dir / "out").string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK(r.output.find("beta capped at 1 on " + std::to_string(b.beta_capped_points) + " of 100") !=
        std::string::npos);
  const auto summary = read_json(dir / "out" / "summary.json");
  const auto& beta = summary["bodies"][0]["beta"];
  CHECK(beta["policy"] == "capped");
  CHECK(beta["capped_points"] == b.beta_capped_points);
  CHECK(beta["max_raw"].get<double>() == Approx(b.beta_max_raw));
}
