#pragma once
// Value generators of a sweep: evenly spaced ranges (linear or logarithmic) and seeded samples
// of a box of parameters (independent uniform draws, or a Latin hypercube: each parameter's
// range cut into N equal strata, each stratum sampled once). Reproducible across compilers and
// standard libraries: the draws come from std::mt19937_64 turned into doubles by hand.
#include <cstdint>
#include <string>
#include <vector>

namespace ckpd::sweep {

// `count` values from `from` to `to` inclusive (count 1: just `from`). Log spacing needs both
// ends positive. The last value is exactly `to`.
std::vector<double> linear_range(double from, double to, int count);
std::vector<double> log_range(double from, double to, int count);

// One sampled dimension: [low, high], uniform in the value or in its logarithm.
struct SampleRange {
  double low = 0, high = 1;
  bool log = false;
};

// samples[run][dimension].
std::vector<std::vector<double>> random_samples(const std::vector<SampleRange>& dims, int count,
                                                std::uint64_t seed);
std::vector<std::vector<double>> latin_hypercube(const std::vector<SampleRange>& dims, int count,
                                                 std::uint64_t seed);

// Shortest text that reads back as the same double ("0.01", "1e-05", "31.622776601683793").
std::string format_number(double value);

}  // namespace ckpd::sweep
