#include "src/geometry/work_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace ckpd {

namespace {
std::uint64_t configured_budget = 0;  // 0: use the machine's available memory
}

std::uint64_t saturating_add(std::uint64_t a, std::uint64_t b) {
  std::uint64_t r = 0;
  return __builtin_add_overflow(a, b, &r) ? kSaturated : r;
}

std::uint64_t saturating_mul(std::uint64_t a, std::uint64_t b) {
  std::uint64_t r = 0;
  return __builtin_mul_overflow(a, b, &r) ? kSaturated : r;
}

std::uint64_t saturating_count(double x) {
  if (std::isnan(x)) return kSaturated;
  if (x <= 0) return 0;
  const double up = std::ceil(x);
  // 2^64 is exactly representable; every double below it converts without overflow.
  if (up >= 18446744073709551616.0) return kSaturated;
  return static_cast<std::uint64_t>(up);
}

std::uint64_t lattice_site_count(const Bounds& b, int dimension, double dx) {
  std::uint64_t sites = 1;
  for (int d = 0; d < dimension; ++d) {
    // The extent itself may overflow to infinity (hi - lo of +-1e308): that saturates too.
    const double cells = std::round((b.hi[d] - b.lo[d]) / dx);
    sites = saturating_mul(sites, std::max<std::uint64_t>(1, saturating_count(cells)));
  }
  return sites;
}

std::uint64_t family_size_estimate(int dimension, double horizon_ratio) {
  const double m = horizon_ratio;
  const double cells = dimension == 3 ? 4.0 / 3.0 * M_PI * m * m * m : M_PI * m * m;
  return saturating_count(cells);
}

std::uint64_t body_bytes_estimate(std::uint64_t points, std::uint64_t family) {
  return saturating_add(saturating_mul(points, kBytesPerPoint),
                        saturating_mul(saturating_mul(points, family), kBytesPerBond));
}

void set_default_memory_budget(std::uint64_t bytes) {
  configured_budget = bytes;
}

std::optional<std::uint64_t> machine_available_memory() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  std::uint64_t kib = 0;
  std::string unit;
  while (in >> key >> kib >> unit)
    if (key == "MemAvailable:") return saturating_mul(kib, 1024);
  return std::nullopt;
}

std::uint64_t default_memory_budget() {
  if (configured_budget) return configured_budget;
  return machine_available_memory().value_or(0);
}

std::string format_count(std::uint64_t n) {
  if (n == kSaturated) return "over 1.8e+19";
  std::ostringstream s;
  if (n < 10'000'000)
    s << n;
  else
    s << std::setprecision(3) << static_cast<double>(n);
  return s.str();
}

std::string format_bytes(std::uint64_t bytes) {
  if (bytes == kSaturated) return "over 1.8e+19 bytes";
  std::ostringstream s;
  s << std::setprecision(3);
  if (bytes >= 1'000'000'000)
    s << static_cast<double>(bytes) / 1e9 << " GB";
  else if (bytes >= 1'000'000)
    s << static_cast<double>(bytes) / 1e6 << " MB";
  else
    s << bytes << " bytes";
  return s.str();
}

}  // namespace ckpd
