// Bad mesh input through the `ckpd` program: each is an error that names the case file, the key
// and what was wrong, with exit status 2.
#include <catch2/catch.hpp>

#include "mesh_fixtures.hpp"
#include "run_helpers.hpp"

using namespace ckpd;
using namespace ckpd::testing;

namespace {

// A case with one body sampled from `geometry` (a flow map) and `extra` body keys.
std::string mesh_case(const std::string& geometry, const std::string& extra = "") {
  return "# SI units\n"
         "materials:\n  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.25}\n"
         "bodies:\n  - {name: part, material: steel, spacing: 0.002, horizon_ratio: 3.015, "
         "geometry: " +
         geometry + extra + "}\ntime: {steps: 2}\n";
}

void expect_error(const std::filesystem::path& dir, const std::string& text,
                  std::initializer_list<std::string> fragments) {
  const std::string file = write_file(dir / "case.yaml", text);
  const CommandResult r = run_ckpd("check " + file);
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("case.yaml:") != std::string::npos);
  for (const std::string& f : fragments) CHECK(r.output.find(f) != std::string::npos);
}

}  // namespace

TEST_CASE("bad mesh input is an error naming the file and what was wrong", "[mesh]") {
  const auto dir = fresh_dir("mesh-errors");
  TriangleMesh cube = cube_mesh(0.02);
  write_obj(cube, (dir / "cube.obj").string());

  SECTION("a good mesh passes, and check reports it") {
    const std::string file =
        write_file(dir / "case.yaml", mesh_case("{type: mesh, file: cube.obj}"));
    const CommandResult r = run_ckpd("check " + file + " --steps 0");
    INFO(r.output);
    CHECK(r.exit_code == 0);
    CHECK(r.output.find("12 triangles") != std::string::npos);
    CHECK(r.output.find("closed, mesh volume 8e-06 m^3") != std::string::npos);
    CHECK(r.output.find("1000 points") != std::string::npos);
  }
  SECTION("missing file") {
    expect_error(dir, mesh_case("{type: mesh, file: nowhere.stl}"),
                 {"geometry.file", "nowhere.stl does not exist"});
  }
  SECTION("unknown format") {
    write_file(dir / "cube.xyz", "1 2 3\n");
    expect_error(dir, mesh_case("{type: mesh, file: cube.xyz}"),
                 {"geometry.file", "a mesh format that assimp reads", ".xyz"});
  }
  SECTION("a PLY header with a count that is not a number") {
    write_file(dir / "broken.ply", "ply\nformat ascii 1.0\nelement vertex banana\nend_header\n");
    expect_error(
        dir, mesh_case("{type: mesh, file: broken.ply}"),
        {"geometry.file", "'element NAME COUNT' lines with a whole COUNT", "header line 3"});
  }
  SECTION("a PLY header cut short before end_header is refused at once") {
    // assimp's importer spent its two-minute CPU limit on it.
    std::filesystem::copy_file(
        std::string(CKPD_SOURCE_DIR) + "/tests/data/inputs/truncated_header.ply", dir / "cut.ply");
    const std::string file =
        write_file(dir / "case.yaml", mesh_case("{type: mesh, file: cut.ply}"));
    const TimedResult r = run_ckpd_within(60, "check " + file);
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("geometry.file") != std::string::npos);
    CHECK(r.output.find("a header that ends in an end_header line") != std::string::npos);
    CHECK(r.seconds < 10);
  }
  SECTION("PLY element counts beyond the file's size are refused") {
    write_file(dir / "short.ply",
               "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\n"
               "property float x\nproperty float y\nproperty float z\nend_header\n0123");
    expect_error(dir, mesh_case("{type: mesh, file: short.ply}"),
                 {"element counts that fit in the file (1000000000 vertex need at least 1.2e+10 "
                  "bytes after the header, the file has 4"});
  }
  SECTION("a file assimp cannot parse") {
    write_file(dir / "broken.obj", "v 0 0 0\nf 1 2 3\n");
    expect_error(dir, mesh_case("{type: mesh, file: broken.obj}"),
                 {"geometry.file", "a mesh file assimp can parse"});
  }
  SECTION("open mesh: how many open edges and where") {
    TriangleMesh open = cube;
    open.triangle.pop_back();
    write_obj(open, (dir / "open.obj").string());
    expect_error(dir, mesh_case("{type: mesh, file: open.obj}"),
                 {"not closed", "3 open edges (holes), the first at (", "inside_test: tolerant"});
  }
  SECTION("mesh with no faces (points and lines only)") {
    write_file(dir / "lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\n");
    expect_error(dir, mesh_case("{type: mesh, file: lines.obj}"),
                 {"a mesh with triangles", "no faces"});
  }
  SECTION("inverted normals") {
    TriangleMesh inverted = cube;
    for (auto& t : inverted.triangle) std::swap(t[1], t[2]);
    write_obj(inverted, (dir / "inverted.obj").string());
    expect_error(dir, mesh_case("{type: mesh, file: inverted.obj}"),
                 {"normals point inwards", "flip"});
  }
  SECTION("inconsistent orientation") {
    TriangleMesh mixed = cube;
    std::swap(mixed.triangle[0][1], mixed.triangle[0][2]);
    write_obj(mixed, (dir / "mixed.obj").string());
    expect_error(dir, mesh_case("{type: mesh, file: mixed.obj}"), {"inconsistent orientation"});
  }
  SECTION("zero scale") {
    expect_error(dir, mesh_case("{type: mesh, file: cube.obj, scale: 0}"),
                 {"geometry.scale", "positive"});
  }
  SECTION("a sampling over the point limit gives the estimate") {
    expect_error(dir, mesh_case("{type: mesh, file: cube.obj}", ", max_points: 500"),
                 {"about 1000 points (mesh volume / dx^3)", "max_points of 500"});
  }
  SECTION("a mesh geometry on a 2D body") {
    expect_error(dir, mesh_case("{type: mesh, file: cube.obj}", ", dimension: 2"),
                 {"a 3D body for a mesh geometry"});
  }
  SECTION("a free mesh wall needs a closed surface") {
    TriangleMesh open = cube;
    open.triangle.pop_back();
    write_obj(open, (dir / "open.obj").string());
    const std::string text =
        "materials:\n  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.25}\n"
        "bodies:\n  - {name: ball, material: steel, spacing: 0.002, horizon_ratio: 3.015, "
        "geometry: {type: sphere, center: [0, 0, 0.03], radius: 0.005}}\n"
        "  - {name: wall, material: steel, rigid: {motion: free}, mesh_wall: {file: open.obj}}\n"
        "time: {steps: 2}\n";
    expect_error(dir, text, {"mesh_wall.file", "not closed"});
  }
}
