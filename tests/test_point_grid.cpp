// The cell list against the plain definition: every binned point within the radius of a query
// is visited exactly once, with its own position and volume, in the same order on every build.
#include <catch2/catch.hpp>
#include <map>
#include <random>

#include "contact/point_grid.hpp"

using namespace ckpd;

TEST_CASE("the point grid visits every member within the radius once, in a fixed order",
          "[contact][point_grid]") {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0, 1);
  const std::size_t n = 3000;
  std::vector<Vec3> reference(n), displacement(n, Vec3::Zero());
  std::vector<double> volume(n);
  for (std::size_t i = 0; i < n; ++i) {
    reference[i] = Vec3(u(rng), u(rng), 0.2 * u(rng));
    volume[i] = 1 + i;
  }
  PointSet points;
  points.reference = reference;
  points.displacement = displacement;
  points.volume = volume;
  std::vector<std::uint32_t> members;
  for (std::uint32_t i = 0; i < n; ++i)
    if (i % 3) members.push_back(i);
  for (double radius : {0.01, 0.07, 0.5}) {
    PointGrid grid;
    grid.build(points, members, radius);
    REQUIRE(grid.size() == members.size());
    for (int q = 0; q < 200; ++q) {
      const Vec3 x(1.2 * u(rng) - 0.1, 1.2 * u(rng) - 0.1, 0.4 * u(rng) - 0.1);
      std::map<std::uint32_t, int> seen;
      std::vector<std::uint32_t> order;
      grid.for_each_near(x, [&](std::uint32_t j, const Vec3& xj, double vj) {
        ++seen[j];
        order.push_back(j);
        REQUIRE(xj == points.position(j));
        REQUIRE(vj == volume[j]);
      });
      for (const auto& [j, count] : seen) REQUIRE(count == 1);
      for (std::uint32_t j : members)
        if ((points.position(j) - x).norm() < radius) REQUIRE(seen.count(j) == 1);
      for (const auto& [j, count] : seen) REQUIRE(j % 3 != 0);  // members only
      PointGrid again;
      again.build(points, members, radius);
      std::vector<std::uint32_t> second;
      again.for_each_near(x, [&](std::uint32_t j, const Vec3&, double) { second.push_back(j); });
      REQUIRE(second == order);
    }
  }
}
