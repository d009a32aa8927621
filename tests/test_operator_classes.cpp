// Row classes of the far field's linear operator (bodies/operator_classes.hpp): on a lattice the
// class operator equals every point's own row (reference_linear_operator) to round-off, 2D and
// 3D, both force forms, with and without failed bonds, at 1 and 2 threads bit for bit, while
// storing far fewer rows and assembling fewer still (rows turned by a lattice symmetry); a point
// whose members hold a failed bond keeps its own row; on a jittered cloud every point is its own
// class and the operator is the same bit for bit.
#include <omp.h>

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "bodies/body.hpp"
#include "bodies/linear_operator.hpp"
#include "bodies/operator_classes.hpp"
#include "kernel_comparison.hpp"

using ckpd::Body;
using ckpd::ForceForm;

namespace {

Body lattice_or_cloud(const kernel_comparison::Scene& s, ForceForm form, double failed) {
  using namespace kernel_comparison;
  std::mt19937 rng(5);
  Body body =
      ckpd::make_body(block(s.dimension, s.nx, s.ny, s.nz, constants_for(s), s.jitter, rng, s.m));
  body.force_form = form;
  if (failed > 0) fail_bonds(body, failed, rng);
  return body;
}

std::size_t row_length(const Body& body, std::size_t i) {
  return 1 + body.family.family_size(i);
}

// The largest block difference of each row relative to the row's largest block.
double worst_row_difference(const Body& body, const ckpd::LinearOperator& a,
                            const ckpd::LinearOperator& b) {
  double worst = 0;
  for (std::size_t i = 0; i < body.size(); ++i) {
    double scale = 0, diff = 0;
    for (std::size_t k = 0; k < row_length(body, i); ++k) {
      scale = std::max(scale, b.block[b.row[i] + k].cwiseAbs().maxCoeff());
      diff = std::max(diff, (a.block[a.row[i] + k] - b.block[b.row[i] + k]).cwiseAbs().maxCoeff());
    }
    worst = std::max(worst, diff / scale);
  }
  return worst;
}

}  // namespace

TEST_CASE("the row-class operator equals every point's own row to round-off on lattices",
          "[far_field]") {
  kernel_comparison::ThreadCountGuard guard;
  const std::vector<kernel_comparison::Scene> lattices = {
      // A row reads two horizons around its point (the members' effective volumes), so only
      // points farther than that from a face share the interior's row along that axis.
      {"2D lattice 40 x 32, nu=0.4", 2, 0.4, 0.0, 40, 32, 1},
      {"3D lattice 20 x 18 x 4, m = 2.015, nu=0.3", 3, 0.3, 0.0, 20, 18, 4, false, 2.015},
  };
  for (const auto& s : lattices)
    for (const ForceForm form : {ForceForm::own_family, ForceForm::energy_consistent})
      for (const double failed : {0.0, 0.0003}) {
        Body body = lattice_or_cloud(s, form, failed);
        omp_set_num_threads(1);
        const ckpd::LinearOperator own = ckpd::reference_linear_operator(body);
        const ckpd::LinearOperator shared = ckpd::linear_operator_by_class(body);
        const ckpd::RowClasses classes = ckpd::operator_row_classes(body);
        INFO(s.label << ", " << ckpd::to_string(form) << ", failed fraction " << failed << ": "
                     << shared.classes << " classes of " << body.size() << " points, "
                     << shared.assembled << " assembled");
        // Each assembled class's first point has its own row bit for bit (the same centres, in
        // the same order, reach it); the others differ by the rounding of their positions and
        // (turned rows) of the sums' order only.
        for (std::size_t i = 0; i < body.size(); ++i)
          if (classes.first[i] == i && classes.source[i] == i)
            for (std::size_t k = 0; k < row_length(body, i); ++k)
              REQUIRE(shared.block[shared.row[i] + k] == own.block[own.row[i] + k]);
        CHECK(worst_row_difference(body, shared, own) <= 1e-12);
        // Far fewer rows than points: the interior and every face band share rows (a few
        // failed bonds give their neighbourhoods rows of their own).
        CHECK(shared.classes * (failed > 0 ? 2 : 4) < body.size());
        CHECK(shared.bytes() * (failed > 0 ? 2 : 4) < own.bytes());
        omp_set_num_threads(2);
        const ckpd::LinearOperator two = ckpd::linear_operator_by_class(body);
        CHECK(two.row == shared.row);
        CHECK(two.block == shared.block);
      }
}

TEST_CASE("the lattice symmetries are the 48 signed axis permutations, the plane's 8 first",
          "[far_field]") {
  const auto& all = ckpd::lattice_symmetries();
  std::set<std::pair<std::array<int, 3>, std::array<int, 3>>> distinct;
  for (std::size_t k = 0; k < all.size(); ++k) {
    std::array<int, 3> sorted = all[k].perm;
    std::sort(sorted.begin(), sorted.end());
    CHECK(sorted == std::array<int, 3>{0, 1, 2});
    for (int sign : all[k].sign) CHECK(std::abs(sign) == 1);
    CHECK((k < ckpd::lattice_symmetry_count(2)) == (all[k].perm[2] == 2 && all[k].sign[2] == 1));
    distinct.insert({all[k].perm, all[k].sign});
  }
  CHECK(distinct.size() == 48);
  CHECK(all[0].perm == std::array<int, 3>{0, 1, 2});
  CHECK(all[0].sign == std::array<int, 3>{1, 1, 1});
}

TEST_CASE("rows turned by a lattice symmetry equal the points' own rows to round-off",
          "[far_field]") {
  kernel_comparison::ThreadCountGuard guard;
  // Square and cube blocks: the corners, edges and faces fall into orbits of up to 8 (2D) and
  // 48 (3D), turned by reflections and by quarter turns (S != S^T, so a transpose mixed up in
  // the turn shows).
  const std::vector<kernel_comparison::Scene> lattices = {
      {"2D square lattice 24 x 24, nu=0.3", 2, 0.3, 0.0, 24, 24, 1},
      {"3D cube lattice 10 x 10 x 10, m = 2.015, nu=0.25", 3, 0.25, 0.0, 10, 10, 10, false, 2.015},
  };
  for (const auto& s : lattices)
    for (const ForceForm form : {ForceForm::own_family, ForceForm::energy_consistent}) {
      Body body = lattice_or_cloud(s, form, 0.0);
      omp_set_num_threads(1);
      const ckpd::LinearOperator own = ckpd::reference_linear_operator(body);
      const ckpd::LinearOperator shared = ckpd::linear_operator_by_class(body);
      const ckpd::RowClasses classes = ckpd::operator_row_classes(body);
      INFO(s.label << ", " << ckpd::to_string(form) << ": " << shared.classes << " classes, "
                   << shared.assembled << " assembled");
      CHECK(shared.assembled * (s.dimension == 2 ? 4 : 8) < shared.classes);
      std::size_t turns = 0;  // turned rows whose symmetry is not its own inverse
      for (std::size_t i = 0; i < body.size(); ++i) {
        if (classes.first[i] != i || classes.source[i] == i) continue;
        const ckpd::LatticeSymmetry& S = ckpd::lattice_symmetries()[classes.symmetry[i]];
        // (S S o)_d = sign[d] sign[perm[d]] o_perm[perm[d]]: S S != I for a quarter turn.
        bool involution = true;
        for (std::size_t d = 0; d < 3; ++d) {
          const auto e = static_cast<std::size_t>(S.perm[d]);
          involution &= S.perm[e] == static_cast<int>(d) && S.sign[d] * S.sign[e] == 1;
        }
        turns += !involution;
      }
      CHECK(turns > 0);
      CHECK(worst_row_difference(body, shared, own) <= 1e-12);
      omp_set_num_threads(2);
      const ckpd::LinearOperator two = ckpd::linear_operator_by_class(body);
      CHECK(two.block == shared.block);
    }
}

TEST_CASE("a point whose family holds a failed bond keeps its own operator row", "[far_field]") {
  const kernel_comparison::Scene s{"2D lattice 40 x 32", 2, 0.3, 0.0, 40, 32, 1};
  Body body = lattice_or_cloud(s, ForceForm::energy_consistent, 0.0);
  const std::vector<std::uint32_t> before = ckpd::operator_row_classes(body).first;
  // Fail one bond in the middle, both stored directions.
  const std::size_t i = 16 * 40 + 20, j = i + 1;
  auto entry = [&](std::size_t a, std::size_t b) {
    for (std::size_t k = body.family.offset[a]; k < body.family.offset[a + 1]; ++k)
      if (body.family.neighbour[k] == b) return k;
    FAIL("no bond");
    return std::size_t{0};
  };
  body.bond_intact[entry(i, j)] = 0;
  body.bond_intact[entry(j, i)] = 0;
  const std::vector<std::uint32_t> after = ckpd::operator_row_classes(body).first;
  std::size_t own_rows = 0;
  for (std::size_t p = 0; p < body.size(); ++p) {
    bool near = p == i || p == j;
    for (std::size_t k = body.family.offset[p]; k < body.family.offset[p + 1]; ++k)
      near |= body.family.neighbour[k] == i || body.family.neighbour[k] == j;
    if (near) {
      CHECK(after[p] == p);
      ++own_rows;
    }
    // Before the failure the middle of the lattice shares rows.
    if (p == i) CHECK(before[p] != p);
  }
  CHECK(own_rows > 2);
  const ckpd::LinearOperator own = ckpd::reference_linear_operator(body);
  const ckpd::LinearOperator shared = ckpd::linear_operator_by_class(body);
  CHECK(worst_row_difference(body, shared, own) <= 1e-12);
}

TEST_CASE("on a point cloud every point is its own row class, bit for bit", "[far_field]") {
  for (const auto& s : {kernel_comparison::Scene{"2D jittered cloud", 2, 0.3, 0.2, 12, 10, 1},
                        kernel_comparison::Scene{"3D jittered cloud", 3, 0.25, 0.2, 6, 6, 5}}) {
    Body body = lattice_or_cloud(s, ForceForm::energy_consistent, 0.05);
    const ckpd::LinearOperator own = ckpd::reference_linear_operator(body);
    const ckpd::LinearOperator shared = ckpd::linear_operator_by_class(body);
    INFO(s.label);
    CHECK(shared.classes == body.size());
    CHECK(shared.row == own.row);
    CHECK(shared.block == own.block);
  }
}
