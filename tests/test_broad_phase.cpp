// The FCL broad phase against the plain definition: box pairs overlap when their intervals
// overlap on every axis (touching counts); only members are reported, each pair once, sorted,
// and an update after moves gives the new answer.
#include <catch2/catch.hpp>
#include <random>

#include "contact/broad_phase.hpp"

using namespace ckpd;

namespace {

using Pairs = std::vector<std::pair<std::uint32_t, std::uint32_t>>;

Pairs brute_force(const std::vector<Box3>& boxes, const std::vector<std::size_t>& members) {
  Pairs pairs;
  for (std::size_t m = 0; m < members.size(); ++m)
    for (std::size_t n = m + 1; n < members.size(); ++n) {
      const Box3 &a = boxes[members[m]], &b = boxes[members[n]];
      if ((a.lo.array() <= b.hi.array()).all() && (b.lo.array() <= a.hi.array()).all())
        pairs.emplace_back(std::min(members[m], members[n]), std::max(members[m], members[n]));
    }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

std::vector<Box3> random_boxes(std::size_t n, std::mt19937& rng) {
  std::uniform_real_distribution<double> where(0, 10), size(0.2, 2);
  std::vector<Box3> boxes(n);
  for (Box3& b : boxes) {
    b.lo = Vec3(where(rng), where(rng), where(rng));
    b.hi = b.lo + Vec3(size(rng), size(rng), size(rng));
  }
  return boxes;
}

}  // namespace

TEST_CASE("the broad phase reports exactly the overlapping member boxes, before and after moves",
          "[contact][broad_phase]") {
  std::mt19937 rng(4);
  const std::size_t n = 60;
  std::vector<std::size_t> members;
  for (std::size_t b = 0; b < n; ++b)
    if (b % 5 != 2) members.push_back(b);  // every fifth body takes no part
  BroadPhase broad(members);
  for (int round = 0; round < 3; ++round) {
    const std::vector<Box3> boxes = random_boxes(n, rng);
    const Pairs expected = brute_force(boxes, members);
    REQUIRE(!expected.empty());
    CHECK(broad.overlapping_pairs(boxes) == expected);
  }
}

TEST_CASE("boxes that only touch overlap; boxes apart by a hair do not", "[contact][broad_phase]") {
  BroadPhase broad({0, 1});
  std::vector<Box3> boxes{{Vec3::Zero(), Vec3::Ones()}, {Vec3(1, 0, 0), Vec3(2, 1, 1)}};
  CHECK(broad.overlapping_pairs(boxes) == Pairs{{0, 1}});
  boxes[1].lo.x() = 1.001;
  CHECK(broad.overlapping_pairs(boxes).empty());
}
