// The force law's linearisation at the reference state (bodies/linear_operator.hpp), the far
// field's operator: equal to a central finite-difference Jacobian of the reference kernel's
// exact force to 1e-7 (2D and 3D, lattice and jittered cloud, both force forms, both damage
// rules with failed bonds, surface, corner and interior points); a rigid translation gives no
// force; the linear force's error against the exact force shrinks like the strain, and a small
// rigid rotation's like the square of the angle. The parallel assembly is the same bit for bit
// at 1, 2 and 3 threads and equals the serial set-by-set one to round-off.
#include <omp.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "bodies/body.hpp"
#include "bodies/ckpd_model.hpp"
#include "bodies/linear_operator.hpp"
#include "kernel_comparison.hpp"
#include "reference/internal_force.hpp"
#include "reference/linear_operator.hpp"

using ckpd::Body;
using ckpd::DamageRule;
using ckpd::ForceForm;
using ckpd::Vec3;

namespace {

struct OperatorScene {
  kernel_comparison::Scene scene;
  ForceForm form;
  DamageRule rule;
};

Body scene_body(const OperatorScene& os, double failed_fraction) {
  using namespace kernel_comparison;
  const Scene& s = os.scene;
  std::mt19937 rng(11);
  Body body =
      ckpd::make_body(block(s.dimension, s.nx, s.ny, s.nz, constants_for(s), s.jitter, rng, s.m));
  body.force_form = os.form;
  body.damage_rule = os.rule;
  if (failed_fraction > 0) fail_bonds(body, failed_fraction, rng);
  return body;
}

std::vector<Vec3> exact_force(Body& body) {
  ckpd::compute_internal_force(body, false);
  return body.force_density;
}

std::string label(const OperatorScene& os) {
  return os.scene.label + ", " + ckpd::to_string(os.form) + ", " + ckpd::to_string(os.rule);
}

const std::vector<OperatorScene>& scenes() {
  static const std::vector<OperatorScene> all = [] {
    std::vector<OperatorScene> v;
    const std::vector<kernel_comparison::Scene> geometry = {
        {"2D lattice, nu=0.4 (C2>0)", 2, 0.4, 0.0, 9, 8, 1},
        {"2D jittered cloud, nu=0.3", 2, 0.3, 0.2, 9, 8, 1},
        {"3D lattice, nu=0.3", 3, 0.3, 0.0, 5, 5, 4},
        {"3D jittered cloud, triangles too", 3, 0.25, 0.2, 5, 5, 4, true},
    };
    for (const auto& g : geometry)
      for (const ForceForm f : {ForceForm::own_family, ForceForm::energy_consistent})
        for (const DamageRule r : {DamageRule::centre_bonds, DamageRule::all_edges})
          v.push_back({g, f, r});
    return v;
  }();
  return all;
}

}  // namespace

TEST_CASE("the linear operator equals the finite-difference Jacobian of the exact force",
          "[far_field]") {
  for (const OperatorScene& os : scenes()) {
    Body body = scene_body(os, 0.1);
    const ckpd::LinearOperator op = ckpd::reference_linear_operator(body);
    const double h = 1e-7 * kernel_comparison::kDx;
    // Columns of a corner point, a surface point and an interior point.
    const std::size_t n = body.size();
    const std::size_t nx = static_cast<std::size_t>(os.scene.nx);
    const std::size_t ny = static_cast<std::size_t>(os.scene.ny);
    const std::size_t interior = os.scene.dimension == 3 ? nx * ny * 2 + nx * 2 + 2 : nx * 4 + 4;
    for (const std::size_t c : {std::size_t{0}, nx / 2, interior}) {
      REQUIRE(c < n);
      for (int axis = 0; axis < os.scene.dimension; ++axis) {
        std::vector<Vec3> plus, minus;
        body.displacement.assign(n, Vec3::Zero());
        body.displacement[c][axis] = h;
        plus = exact_force(body);
        body.displacement[c][axis] = -h;
        minus = exact_force(body);
        body.displacement[c][axis] = 0;
        // Column (c, axis) of the operator, row by row.
        double scale = 0, worst = 0;
        for (std::size_t i = 0; i < n; ++i) {
          const Vec3 fd = (plus[i] - minus[i]) / (2 * h);
          Vec3 column = Vec3::Zero();
          if (i == c) column = op.block[op.row[i]].col(axis);
          std::size_t slot = 1;
          for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k, ++slot)
            if (body.family.neighbour[k] == c) column = op.block[op.row[i] + slot].col(axis);
          scale = std::max(scale, fd.norm());
          worst = std::max(worst, (column - fd).norm());
        }
        INFO(label(os) << ", column of point " << c << " axis " << axis << ": |K - FD| " << worst
                       << " of " << scale);
        REQUIRE(scale > 0);
        CHECK(worst <= 1e-7 * scale);
      }
    }
  }
}

TEST_CASE("a rigid translation gives no linear force", "[far_field]") {
  for (const OperatorScene& os : scenes()) {
    Body body = scene_body(os, 0.1);
    const ckpd::LinearOperator op = ckpd::reference_linear_operator(body);
    body.displacement.assign(body.size(), Vec3(1e-6, -2e-6, os.scene.dimension == 3 ? 3e-6 : 0));
    std::vector<Vec3> b;
    ckpd::apply_linear_operator(op, body, b);
    // Against the forces one component's displacement alone would give a point.
    double diagonal = 0;
    for (std::size_t i = 0; i < body.size(); ++i)
      diagonal = std::max(diagonal, op.block[op.row[i]].norm() * 1e-6);
    INFO(label(os));
    CHECK(kernel_comparison::max_norm(b) <= 1e-12 * diagonal);
  }
}

TEST_CASE("the linear force's error shrinks like the strain, a rotation's like its square",
          "[far_field]") {
  std::mt19937 rng(3);
  for (const OperatorScene& os : scenes()) {
    if (os.rule != DamageRule::all_edges) continue;  // the rule does not change the scaling
    Body body = scene_body(os, 0.0);
    const ckpd::LinearOperator op = ckpd::reference_linear_operator(body);
    // A smooth random strain field u = G X (no rotation: G symmetric) plus noise.
    Eigen::Matrix3d G = Eigen::Matrix3d::Random();
    G = 0.5 * (G + G.transpose()).eval();
    if (os.scene.dimension == 2) G.row(2).setZero(), G.col(2).setZero();
    auto relative_error = [&](double amplitude, bool rotation) {
      for (std::size_t i = 0; i < body.size(); ++i) {
        const Vec3 X = body.reference_position[i] - body.reference_position[0];
        if (rotation) {  // about z by the angle `amplitude`, exactly
          const double c = std::cos(amplitude), s = std::sin(amplitude);
          body.displacement[i] = Vec3(c * X.x() - s * X.y(), s * X.x() + c * X.y(), X.z()) - X;
        } else {
          body.displacement[i] = amplitude * (G * X);
        }
      }
      const std::vector<Vec3> exact = exact_force(body);
      std::vector<Vec3> linear;
      ckpd::apply_linear_operator(op, body, linear);
      double err = 0, ref = 0;
      for (std::size_t i = 0; i < body.size(); ++i) {
        err = std::max(err, (linear[i] - exact[i]).norm());
        ref = std::max(ref, exact[i].norm());
      }
      return std::pair{err, ref};
    };
    const auto [e3, f3] = relative_error(1e-3, false);
    const auto [e4, f4] = relative_error(1e-4, false);
    const double slope = std::log10((e3 / f3) / (e4 / f4));
    // Rotation: the exact force is zero, the linear one is of second order in the angle.
    const auto [r3, g3] = relative_error(1e-3, true);
    const auto [r4, g4] = relative_error(1e-4, true);
    const double rotation_slope = std::log10(r3 / r4);
    INFO(label(os) << ": strain error " << e3 / f3 << " at 1e-3, " << e4 / f4 << " at 1e-4 (slope "
                   << slope << "); rotation error " << r3 << " at 1e-3, " << r4
                   << " at 1e-4 (slope " << rotation_slope << "), exact force " << g3);
    CHECK(slope == Approx(1.0).margin(0.15));
    CHECK(rotation_slope == Approx(2.0).margin(0.15));
    CHECK(e3 / f3 < 1e-2);
  }
}

TEST_CASE(
    "the parallel operator assembly is the same bit for bit at every thread count and the "
    "serial assembly to round-off",
    "[far_field]") {
  kernel_comparison::ThreadCountGuard guard;
  for (const OperatorScene& os : scenes()) {
    Body body = scene_body(os, 0.1);
    omp_set_num_threads(1);
    const ckpd::LinearOperator one = ckpd::reference_linear_operator(body);
    ckpd::LinearOperator serial = one;
    for (auto& b : serial.block) b.setZero();
    ckpd::assemble_linear_operator_serial_of(ckpd::CkpdModel::of(body), body, serial);
    INFO(label(os));
    for (int threads : {2, 3}) {
      omp_set_num_threads(threads);
      const ckpd::LinearOperator many = ckpd::reference_linear_operator(body);
      INFO(threads << " threads");
      CHECK(many.row == one.row);
      CHECK(many.block == one.block);
    }
    // Both assemblies against the same terms summed in long double, per row relative to the
    // row's largest sum of term magnitudes. The terms of lattice tetrahedra are many and alike
    // (3D lattice: errors of both assemblies near 3e-13 of those magnitudes), so the test asks
    // that the parallel sums (a centre's sets first) be no less accurate than the serial ones.
    using Block = Eigen::Matrix<long double, 3, 3>;
    std::vector<Block> accurate(one.block.size(), Block::Zero());
    std::vector<Eigen::Matrix3d> magnitude(one.block.size(), Eigen::Matrix3d::Zero());
    const bool all_rows = body.force_form == ForceForm::energy_consistent;
    ckpd::FamilyScratch s;
    std::vector<std::size_t> table;
    for (std::size_t c = 0; c < body.size(); ++c) {
      s.load(body, c, body.damage_enabled, true);
      ckpd::linear_operator_detail::column_table(body, static_cast<std::uint32_t>(c), s, table);
      const std::size_t m = s.size() + 1;
      ckpd::linear_operator_detail::for_each_set(
          ckpd::CkpdModel::of(body), body, c, s,
          [&](const auto& lin, const auto& vertex, const auto& slot, const auto& scale) {
            const int n = static_cast<int>(std::size(vertex));
            for (int v = 0; v < (all_rows ? n : 1); ++v)
              for (int w = 0; w < n; ++w) {
                const std::size_t k = one.row[vertex[v]] + table[slot[v] * m + slot[w]];
                const Eigen::Matrix3d term = scale[v] * lin.block(v, w);
                magnitude[k] += term.cwiseAbs();
                accurate[k] += term.template cast<long double>();
              }
          });
    }
    double worst = 0, serial_error = 0, parallel_error = 0;
    auto error = [&](const Eigen::Matrix3d& x, std::size_t k) {
      return static_cast<double>((x.cast<long double>() - accurate[k]).cwiseAbs().maxCoeff());
    };
    for (std::size_t i = 0; i < body.size(); ++i) {
      double scale = 0, diff = 0, se = 0, pe = 0;
      for (std::size_t k = one.row[i]; k < one.row[i] + 1 + body.family.family_size(i); ++k) {
        scale = std::max(scale, magnitude[k].maxCoeff());
        diff = std::max(diff, (one.block[k] - serial.block[k]).cwiseAbs().maxCoeff());
        se = std::max(se, error(serial.block[k], k));
        pe = std::max(pe, error(one.block[k], k));
      }
      REQUIRE(scale > 0);
      worst = std::max(worst, diff / scale);
      serial_error = std::max(serial_error, se / scale);
      parallel_error = std::max(parallel_error, pe / scale);
    }
    INFO("relative to the term magnitudes: parallel - serial "
         << worst << ", serial error " << serial_error << ", parallel error " << parallel_error);
    CHECK(worst <= 1e-12);
    CHECK(parallel_error <= 2 * serial_error);
  }
}
