// One-neighbour families H1 (THEORY.md section 1) against a brute-force search.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

#include "bodies/bond_family.hpp"
#include "body_fixtures.hpp"

namespace {

using ckpd::BondFamily;
using ckpd::Vec3;

// O(n^2): every j != i with |X^j - X^i| <= delta (1 + 1e-12), in increasing index order.
std::vector<std::vector<std::uint32_t>> brute_force(const std::vector<Vec3>& X, double delta) {
  std::vector<std::vector<std::uint32_t>> h(X.size());
  for (std::size_t i = 0; i < X.size(); ++i)
    for (std::size_t j = 0; j < X.size(); ++j)
      if (j != i && (X[j] - X[i]).norm() <= delta * (1 + 1e-12))
        h[i].push_back(static_cast<std::uint32_t>(j));
  return h;
}

void check_equals_brute_force(const std::vector<Vec3>& X, double delta) {
  const BondFamily f = ckpd::build_bond_family(X, delta);
  const auto expected = brute_force(X, delta);
  REQUIRE(f.points() == X.size());
  REQUIRE(f.offset.front() == 0);
  REQUIRE(f.offset.back() == f.neighbour.size());
  std::size_t total = 0, mismatches = 0;
  for (std::size_t i = 0; i < X.size(); ++i) {
    const std::vector<std::uint32_t> got(f.neighbour.begin() + f.offset[i],
                                         f.neighbour.begin() + f.offset[i + 1]);
    if (got != expected[i]) ++mismatches;
    total += expected[i].size();
    CHECK(std::is_sorted(got.begin(), got.end()));
    // Symmetric: j in H1(i) iff i in H1(j).
    for (const std::uint32_t j : got) {
      CHECK(j != i);
      const auto b = f.neighbour.begin() + f.offset[j], e = f.neighbour.begin() + f.offset[j + 1];
      CHECK(std::binary_search(b, e, static_cast<std::uint32_t>(i)));
    }
  }
  CHECK(mismatches == 0);
  CHECK(f.bond_entries() == total);
  CHECK(total % 2 == 0);
  CHECK(total > 0);  // the comparison is not vacuous
}

std::vector<Vec3> random_cloud(int dimension, std::size_t n, const Vec3& box, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> X(n, Vec3::Zero());
  for (Vec3& p : X)
    for (int c = 0; c < dimension; ++c) p[c] = box[c] * u(rng);
  return X;
}

}  // namespace

TEST_CASE("bond families equal a brute-force search on random clouds", "[bond_family]") {
  std::mt19937 rng(42);
  SECTION("3D") {
    check_equals_brute_force(random_cloud(3, 600, Vec3(1, 2, 0.5), rng), 0.15);
    check_equals_brute_force(random_cloud(3, 300, Vec3(1, 1, 1), rng), 0.4);
    check_equals_brute_force(random_cloud(3, 200, Vec3(1, 1, 1), rng), 5.0);  // all in one cell
  }
  SECTION("2D") {
    check_equals_brute_force(random_cloud(2, 800, Vec3(3, 1, 0), rng), 0.12);
    check_equals_brute_force(random_cloud(2, 300, Vec3(1, 1, 0), rng), 0.3);
  }
  SECTION("a tiny horizon in a huge box (coarsened cell grid)") {
    std::vector<Vec3> X = random_cloud(3, 150, Vec3(1, 1, 1), rng);
    for (const Vec3& p : random_cloud(3, 150, Vec3(1, 1, 1), rng))
      X.push_back(p + Vec3(1e6, -3e5, 2e5));
    check_equals_brute_force(X, 0.2);
  }
  SECTION("a jittered lattice") {
    const auto d = ckpd_test::jittered_cloud(3, 7, 6, 5, 0.01, 2.6, {1, 0, 1}, 0.3, rng);
    check_equals_brute_force(d.reference_position, d.horizon);
  }
}

TEST_CASE("a neighbour at exactly the horizon is in the family, just beyond it is not",
          "[bond_family]") {
  const double delta = 0.3;
  const std::vector<Vec3> X = {Vec3(0, 0, 0), Vec3(delta, 0, 0), Vec3(0, delta * (1 + 1e-9), 0),
                               Vec3(0, 0, -delta)};
  const BondFamily f = ckpd::build_bond_family(X, delta);
  const std::vector<std::uint32_t> h0(f.neighbour.begin() + f.offset[0],
                                      f.neighbour.begin() + f.offset[1]);
  CHECK(h0 == std::vector<std::uint32_t>{1, 3});
  CHECK(f.family_size(2) == 0);
}

TEST_CASE("interior lattice points have the lattice's neighbour count", "[bond_family]") {
  struct Case {
    int dimension;
    double m, dx;
    std::size_t expected;
  };
  const std::vector<Case> cases = {
      {3, 3.015, 1.125e-3, 122}, {3, 2.015, 16.7e-3, 32}, {2, 3.015, 5e-3, 28},
      {2, 2.015, 1.0, 12},       {3, 3.0, 0.1, 0},        {2, 4.0, 0.1, 0},
  };
  for (const Case& c : cases) {
    INFO("dimension " << c.dimension << ", m " << c.m << ", dx " << c.dx);
    // Offsets at exactly m dx (m = 3, 4) are bonds up to round-off on every machine.
    const std::size_t expected =
        c.expected ? c.expected
                   : static_cast<std::size_t>(ckpd_test::lattice_offsets_within(c.dimension, c.m));
    const int h = static_cast<int>(std::floor(c.m + 1e-9));  // the longest axis offset
    const int n = 2 * h + 3;
    const auto d =
        ckpd_test::lattice_block(c.dimension, n, n, c.dimension == 3 ? n : 1, c.dx, c.m, {1, 0, 0});
    const BondFamily f = ckpd::build_bond_family(d.reference_position, d.horizon);
    std::size_t interior = 0;
    for (std::size_t i = 0; i < d.reference_position.size(); ++i) {
      const Vec3 p = d.reference_position[i] / c.dx;
      bool inside = true;
      for (int k = 0; k < c.dimension; ++k)
        inside &= std::round(p[k]) >= h && std::round(p[k]) <= n - 1 - h;
      if (!inside) {
        CHECK(f.family_size(i) < expected);
        continue;
      }
      ++interior;
      CHECK(f.family_size(i) == expected);
    }
    CHECK(interior > 0);
  }
  CHECK(ckpd_test::lattice_offsets_within(3, 3.0) == 122);
  CHECK(ckpd_test::lattice_offsets_within(2, 4.0) == 48);
}

TEST_CASE("building a family rejects non-finite positions and a non-positive horizon",
          "[bond_family]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const Vec3& bad : {Vec3(nan, 0, 0), Vec3(0, inf, 0), Vec3(0, 0, -inf)}) {
    const std::vector<Vec3> X = {Vec3(0, 0, 0), Vec3(1, 0, 0), bad, Vec3(0, 1, 0)};
    CHECK_THROWS_AS(ckpd::build_bond_family(X, 1.5), std::invalid_argument);
  }
  const std::vector<Vec3> X = {Vec3(0, 0, 0), Vec3(1, 0, 0)};
  CHECK_THROWS_AS(ckpd::build_bond_family(X, 0.0), std::invalid_argument);
  CHECK_THROWS_AS(ckpd::build_bond_family(X, -1.0), std::invalid_argument);
  CHECK_THROWS_AS(ckpd::build_bond_family(X, nan), std::invalid_argument);
  CHECK(ckpd::build_bond_family(X, 1.0).bond_entries() == 2);
  CHECK(ckpd::build_bond_family({}, 1.0).points() == 0);
}
