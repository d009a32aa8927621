// Strain fields: under a homogeneous deformation x = F X of a lattice, the non-local deformation
// gradient is F at every point (surface points too), the Green-Lagrange strain (F^T F - I)/2 and
// the dilatation det F - 1; a point whose bonds have all failed has none (NaN).
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "run_helpers.hpp"
#include "src/case/case_loader.hpp"
#include "src/engine/simulation.hpp"
#include "src/output/field_table.hpp"

using namespace ckpd;
using namespace ckpd::testing;

namespace {

std::string block_case(int dimension) {
  const std::string box = dimension == 3 ? "{type: box, min: [0, 0, 0], max: [0.005, 0.004, 0.003]}"
                                         : "{type: box, min: [0, 0], max: [0.006, 0.004]}";
  return "materials:\n  m: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.25}\n"
         "bodies:\n  - {name: block, material: m, dimension: " +
         std::to_string(dimension) + ", geometry: " + box +
         ", spacing: 0.001, horizon_ratio: 2.015}\n"
         "time: {steps: 1}\n";
}

}  // namespace

TEST_CASE("a homogeneous deformation gives its F, strain and dilatation at every point",
          "[output][strain]") {
  for (int dimension : {2, 3}) {
    INFO(dimension << "D");
    const auto dir = fresh_dir("strain");
    Scene scene = load_scene(write_file(dir / "case.yaml", block_case(dimension)));
    Simulation sim(scene);
    Body& body = scene.bodies[0].body;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-0.05, 0.05);
    Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
    for (int r = 0; r < dimension; ++r)
      for (int c = 0; c < dimension; ++c) F(r, c) += u(rng);
    const Vec3 shift(1e-4, -2e-4, dimension == 3 ? 3e-4 : 0.0);
    for (std::size_t i = 0; i < body.size(); ++i)
      body.displacement[i] = (F - Eigen::Matrix3d::Identity()) * body.reference_position[i] + shift;
    std::vector<double> grad, strain, dil;
    find_field("deformation_gradient")->extract({body, 0}, grad);
    find_field("green_lagrange_strain")->extract({body, 0}, strain);
    find_field("dilatation")->extract({body, 0}, dil);
    const Eigen::Matrix3d E = 0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity());
    const double expected_strain[6] = {E(0, 0), E(0, 1), E(0, 2), E(1, 1), E(1, 2), E(2, 2)};
    double worst = 0;
    for (std::size_t i = 0; i < body.size(); ++i) {
      for (int k = 0; k < 9; ++k)
        worst = std::max(worst, std::abs(grad[9 * i + k] - F(k / 3, k % 3)));
      for (int k = 0; k < 6; ++k)
        worst = std::max(worst, std::abs(strain[6 * i + k] - expected_strain[k]));
      worst = std::max(worst, std::abs(dil[i] - (F.determinant() - 1)));
    }
    CHECK(worst < 1e-12);
  }
}

TEST_CASE("a point with every bond failed has no deformation gradient", "[output][strain]") {
  const auto dir = fresh_dir("strain-broken");
  Scene scene = load_scene(write_file(dir / "case.yaml", block_case(2)));
  Simulation sim(scene);
  Body& body = scene.bodies[0].body;
  for (std::size_t k = body.family.offset[0]; k < body.family.offset[1]; ++k)
    body.bond_intact[k] = 0;
  std::vector<double> dil;
  find_field("dilatation")->extract({body, 0}, dil);
  CHECK(std::isnan(dil[0]));
  CHECK(dil[1] == Approx(0).margin(1e-14));
}
