// The work and memory estimates saturate instead of wrapping: at the limits of 64-bit counts,
// for extents that overflow to infinity, and for NaN.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "src/geometry/lattice.hpp"
#include "src/geometry/work_estimate.hpp"

using namespace ckpd;

TEST_CASE("saturating arithmetic is exact below 2^64 and saturates at it", "[estimate]") {
  const std::uint64_t max = kSaturated;
  CHECK(saturating_add(max - 1, 1) == max);
  CHECK(saturating_add(max, 1) == max);
  CHECK(saturating_add(max / 2, max / 2) == max - 1);
  CHECK(saturating_mul(std::uint64_t{1} << 32, (std::uint64_t{1} << 32) - 1) ==
        (std::uint64_t{1} << 63) + ((std::uint64_t{1} << 63) - (std::uint64_t{1} << 32)));
  CHECK(saturating_mul(std::uint64_t{1} << 32, std::uint64_t{1} << 32) == max);
  CHECK(saturating_mul(0, max) == 0);
}

TEST_CASE("a real count rounds up and saturates for NaN, infinity and 2^64", "[estimate]") {
  CHECK(saturating_count(0.0) == 0);
  CHECK(saturating_count(-5.0) == 0);
  CHECK(saturating_count(2.2) == 3);
  CHECK(saturating_count(9007199254740992.0) == 9007199254740992ull);          // 2^53, exact
  CHECK(saturating_count(18446744073709549568.0) == 18446744073709549568ull);  // below 2^64
  CHECK(saturating_count(18446744073709551616.0) == kSaturated);               // 2^64
  CHECK(saturating_count(std::numeric_limits<double>::infinity()) == kSaturated);
  CHECK(saturating_count(std::numeric_limits<double>::quiet_NaN()) == kSaturated);
}

TEST_CASE("lattice site counts saturate for huge and overflowing boxes", "[estimate]") {
  const Bounds unit{Vec3(0, 0, 0), Vec3(1, 1, 1)};
  CHECK(lattice_site_count(unit, 3, 0.1) == 1000);
  CHECK(lattice_site_count(unit, 2, 0.1) == 100);
  // -1e200 .. 1e200 at 1 mm: the box that wrapped to 25 points.
  const Bounds huge{Vec3(-1e200, -1e200, -1e200), Vec3(1e200, 1e200, 1e200)};
  CHECK(lattice_site_count(huge, 3, 1e-3) == kSaturated);
  // hi - lo overflows to infinity.
  const Bounds overflow{Vec3(-1.7e308, 0, 0), Vec3(1.7e308, 1, 1)};
  CHECK(lattice_site_count(overflow, 3, 1.0) == kSaturated);
  // 2^32 x 2^32 sites: exactly at the limit, one more factor saturates.
  const double side = 4294967296.0;
  CHECK(lattice_site_count(Bounds{Vec3(0, 0, 0), Vec3(side, side, 2)}, 2, 1.0) == kSaturated);
  CHECK(lattice_site_count(Bounds{Vec3(0, 0, 0), Vec3(side, side / 2, 2)}, 2, 1.0) ==
        std::uint64_t{1} << 63);
}

TEST_CASE("the family estimate follows the exact count and stays cheap for any ratio",
          "[estimate]") {
  for (int dimension : {2, 3})
    for (double m : {2.015, 3.015, 4.015, 6.015}) {
      const double exact = static_cast<double>(lattice_family_size(dimension, 1.0, m));
      const double estimate = static_cast<double>(family_size_estimate(dimension, m));
      INFO(dimension << "D, m = " << m);
      CHECK(std::abs(estimate / exact - 1) < 0.12);
    }
  CHECK(family_size_estimate(3, 1e4) > kMaxFamilySize);
  CHECK(family_size_estimate(3, 1e12) == kSaturated);
  // The exact count refuses what would loop (2m + 3)^3 times.
  CHECK_THROWS_AS(lattice_family_size(3, 1.0, 1e4), std::invalid_argument);
}

TEST_CASE("body bytes saturate and format as 'over'", "[estimate]") {
  CHECK(body_bytes_estimate(1000, 100) == 1000 * (kBytesPerPoint + 100 * kBytesPerBond));
  CHECK(body_bytes_estimate(kSaturated / 2, 100) == kSaturated);
  CHECK(format_count(kSaturated) == "over 1.8e+19");
  CHECK(format_bytes(kSaturated) == "over 1.8e+19 bytes");
  CHECK(format_bytes(69'200'000'000ull) == "69.2 GB");
  CHECK(format_count(12345) == "12345");
}
