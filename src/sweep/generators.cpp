#include "src/sweep/generators.hpp"

#include <charconv>
#include <cmath>
#include <random>

namespace ckpd::sweep {

namespace {

// A uniform double in [0, 1) from the top 53 bits of one draw.
double unit(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

double place(const SampleRange& r, double u) {
  if (r.log) return std::exp(std::log(r.low) + u * (std::log(r.high) - std::log(r.low)));
  return r.low + u * (r.high - r.low);
}

}  // namespace

std::vector<double> linear_range(double from, double to, int count) {
  std::vector<double> v;
  for (int i = 0; i < count; ++i)
    v.push_back(count == 1 ? from : from + (to - from) * i / (count - 1));
  if (count > 1) v.back() = to;
  return v;
}

std::vector<double> log_range(double from, double to, int count) {
  std::vector<double> v;
  const double a = std::log(from), b = std::log(to);
  for (int i = 0; i < count; ++i)
    v.push_back(count == 1 ? from : std::exp(a + (b - a) * i / (count - 1)));
  if (count > 1) {
    v.front() = from;
    v.back() = to;
  }
  return v;
}

std::vector<std::vector<double>> random_samples(const std::vector<SampleRange>& dims, int count,
                                                std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<std::vector<double>> out(count, std::vector<double>(dims.size()));
  for (int i = 0; i < count; ++i)
    for (std::size_t d = 0; d < dims.size(); ++d) out[i][d] = place(dims[d], unit(rng));
  return out;
}

std::vector<std::vector<double>> latin_hypercube(const std::vector<SampleRange>& dims, int count,
                                                 std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<std::vector<double>> out(count, std::vector<double>(dims.size()));
  std::vector<int> strata(count);
  for (std::size_t d = 0; d < dims.size(); ++d) {
    for (int i = 0; i < count; ++i) strata[i] = i;
    // Fisher-Yates with our own index draws (std::shuffle's are library-specific).
    for (int i = count - 1; i > 0; --i) std::swap(strata[i], strata[rng() % (i + 1)]);
    for (int i = 0; i < count; ++i) out[i][d] = place(dims[d], (strata[i] + unit(rng)) / count);
  }
  return out;
}

std::string format_number(double value) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, value);
  return std::string(buf, r.ptr);
}

}  // namespace ckpd::sweep
