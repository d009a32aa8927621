// Bodies sampled inside triangle surfaces (`geometry: {type: mesh, ...}`): the sampled volume
// of closed meshes approaches the enclosed volume as dx shrinks; the same surface in four file
// formats (and any triangle order) gives the same points bit for bit; rotating the mesh and
// sampling equals sampling and rotating, up to the lattice.
#include <Eigen/Geometry>
#include <algorithm>
#include <catch2/catch.hpp>
#include <random>

#include "mesh_fixtures.hpp"
#include "run_helpers.hpp"
#include "src/geometry/lattice.hpp"
#include "src/geometry/mesh/mesh_check.hpp"
#include "src/geometry/mesh/mesh_properties.hpp"
#include "src/geometry/mesh/mesh_shape.hpp"

using namespace ckpd;
using namespace ckpd::testing;

namespace {

// Samples `file` (in `dir`) with the extra geometry keys `keys`.
LatticeSample sample_file(const std::filesystem::path& dir, const std::string& file, double dx,
                          const std::string& keys = "") {
  const YAML::Node node = YAML::Load("{type: mesh, file: " + file + keys + "}");
  const auto shape = make_shape(CaseNode(node, (dir / "case.yaml").string()), 3);
  return sample_lattice(*shape, 3, dx, 3 * dx, 50'000'000);
}

LatticeSample sample_mesh(const TriangleMesh& m, double dx, const std::string& keys = "") {
  const auto dir = fresh_dir("mesh-sample");
  write_obj(m, (dir / "m.obj").string());
  return sample_file(dir, "m.obj", dx, keys);
}

double total_volume(const LatticeSample& s) {
  double v = 0;
  for (double x : s.volume) v += x;
  return v;
}

double relative_error(const TriangleMesh& m, double dx) {
  const double exact = diagnose_mesh(m).signed_volume;
  return std::abs(total_volume(sample_mesh(m, dx)) / exact - 1);
}

}  // namespace

TEST_CASE("mesh volume and moments by the divergence theorem match a cube's closed forms",
          "[mesh]") {
  const double a = 0.02;
  const MeshMassProperties p = mesh_mass_properties(cube_mesh(a));
  // The corners are floats (mesh_fixtures.hpp): 0.02 is off by 2e-8 relative.
  CHECK(p.volume == Approx(a * a * a).epsilon(1e-6));
  CHECK((p.centroid - Vec3::Constant(a / 2)).norm() < 1e-9);
  // a^5/6 about every axis through the centre, no products.
  const Eigen::Matrix3d expected = Eigen::Matrix3d::Identity() * std::pow(a, 5) / 6;
  CHECK((p.second_moment - expected).norm() < 1e-6 * expected.norm());
}

TEST_CASE("sampled volume of closed meshes converges to the enclosed volume", "[mesh]") {
  // Tolerances (a cubic lattice's boundary error is O(dx / size), with lattice-dependent
  // scatter): 8 % at 10 cells across the diameter (tube diameter for the torus), 3 % at 20,
  // 1.5 % at 40. Flat faces on cell boundaries are exact up to the float corners (1e-6).
  SECTION("sphere") {
    const TriangleMesh m = sphere_mesh(0.01, 32, 64);
    const double e5 = relative_error(m, 0.002), e10 = relative_error(m, 0.001),
                 e20 = relative_error(m, 0.0005);
    WARN("sphere volume error at D/10, D/20, D/40: " << e5 << ", " << e10 << ", " << e20);
    CHECK(e5 < 0.08);
    CHECK(e10 < 0.03);
    CHECK(e20 < 0.015);
    CHECK(e20 < e5);
  }
  SECTION("cube: cell-centred, exact") {
    CHECK(relative_error(cube_mesh(0.02), 0.002) < 1e-6);
    CHECK(relative_error(cube_mesh(0.02), 0.001) < 1e-6);
  }
  SECTION("torus") {
    const TriangleMesh m = torus_mesh(0.02, 0.008, 96, 48);
    const double e5 = relative_error(m, 0.0016), e20 = relative_error(m, 0.0004);
    WARN("torus volume error at d/10, d/40: " << e5 << ", " << e20);
    CHECK(e5 < 0.08);
    CHECK(e20 < 0.015);
    CHECK(e20 < e5);
  }
  SECTION("notched plate: edges on lattice planes, exact") {
    // 40 x 20 x 4 mm with a 10 mm wide, 8 mm deep notch: every face on a cell boundary.
    const TriangleMesh m = notched_plate_mesh(0.04, 0.02, 0.015, 0.025, 0.008, 0.004);
    CHECK(diagnose_mesh(m).signed_volume == Approx((0.04 * 0.02 - 0.01 * 0.008) * 0.004));
    CHECK(relative_error(m, 0.001) < 1e-6);
    CHECK(relative_error(m, 0.0005) < 1e-6);
  }
}

TEST_CASE("ASCII STL, binary STL, OBJ and PLY of one surface give identical points", "[mesh]") {
  TriangleMesh m = torus_mesh(0.02, 0.007, 48, 24);
  const auto dir = fresh_dir("mesh-formats");
  write_ascii_stl(m, (dir / "t_ascii.stl").string());
  write_binary_stl(m, (dir / "t_binary.stl").string());
  write_obj(m, (dir / "t.obj").string());
  // The PLY with its triangles shuffled and each one's corners rotated: order must not matter.
  TriangleMesh shuffled = m;
  std::mt19937 rng(7);
  std::shuffle(shuffled.triangle.begin(), shuffled.triangle.end(), rng);
  for (auto& t : shuffled.triangle) std::rotate(t.begin(), t.begin() + rng() % 3, t.end());
  write_ply(shuffled, (dir / "t.ply").string());
  const double dx = 0.001;
  const LatticeSample ref = sample_file(dir, "t.obj", dx);
  REQUIRE(ref.position.size() > 1000);
  for (const char* f : {"t_ascii.stl", "t_binary.stl", "t.ply"}) {
    INFO(f);
    const LatticeSample s = sample_file(dir, f, dx);
    REQUIRE(s.position.size() == ref.position.size());
    CHECK(s.position == ref.position);
  }
}

TEST_CASE("rotating the mesh and sampling equals sampling and rotating the points", "[mesh]") {
  const TriangleMesh m = notched_plate_mesh(0.04, 0.02, 0.015, 0.025, 0.008, 0.006);
  const double dx = 0.0005;
  const LatticeSample plain = sample_mesh(m, dx);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const LatticeSample turned = sample_mesh(m, dx,
                                           ", rotation: {axis: [1, 2, 3], degrees: " +
                                               std::to_string(0.7 * 180 / std::numbers::pi) + "}");
  // Compare volume, centroid and second moments of the two point sets (the lattice differs).
  auto moments = [](const LatticeSample& s, const Eigen::Matrix3d& rot, Vec3& centroid,
                    Eigen::Matrix3d& second) {
    centroid.setZero();
    double v = 0;
    for (std::size_t i = 0; i < s.position.size(); ++i) {
      centroid += s.volume[i] * rot * s.position[i];
      v += s.volume[i];
    }
    centroid /= v;
    second.setZero();
    for (std::size_t i = 0; i < s.position.size(); ++i) {
      const Vec3 r = rot * s.position[i] - centroid;
      second += s.volume[i] * r * r.transpose();
    }
    return v;
  };
  Vec3 c1, c2;
  Eigen::Matrix3d s1, s2;
  const double v1 = moments(plain, R, c1, s1),
               v2 = moments(turned, Eigen::Matrix3d::Identity(), c2, s2);
  CHECK(v2 == Approx(v1).epsilon(0.02));
  // The rotation turns the mesh about the origin, as it turns the points.
  CHECK((c1 - c2).norm() < 0.2 * dx);
  CHECK((s1 - s2).norm() < 0.03 * s1.norm());
}

TEST_CASE("tolerant inside test fills a sphere with a hole like the closed one", "[mesh]") {
  TriangleMesh closed = sphere_mesh(0.01, 24, 48);
  TriangleMesh holed = closed;
  holed.triangle.erase(holed.triangle.begin() + 300);  // a hole near the equator... somewhere
  REQUIRE(diagnose_mesh(holed).open_edges.count == 3);
  const double dx = 0.001;
  const LatticeSample a = sample_mesh(closed, dx);
  const LatticeSample b = sample_mesh(holed, dx, ", inside_test: tolerant");
  const double va = total_volume(a), vb = total_volume(b);
  CHECK(vb == Approx(va).epsilon(0.005));
}
