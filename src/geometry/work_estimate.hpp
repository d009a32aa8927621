#pragma once
// What a body will cost before it is built: lattice sites, points, family size, bonds and bytes,
// all in saturating unsigned 64-bit arithmetic (a box from -1e200 to 1e200 at 1 mm must give
// "more than 1.8e19 sites", not a wrapped count of 25), and the memory budget they are refused
// against: the case's `max_memory`, else the machine's available memory (/proc/meminfo
// MemAvailable).
#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include "src/geometry/shape.hpp"

namespace ckpd {

inline constexpr std::uint64_t kSaturated = std::numeric_limits<std::uint64_t>::max();

// Saturating arithmetic: the result is kSaturated when the exact one would not fit.
std::uint64_t saturating_add(std::uint64_t a, std::uint64_t b);
std::uint64_t saturating_mul(std::uint64_t a, std::uint64_t b);
// A non-negative real as a count: rounded up; NaN, infinity and values past 2^64 saturate;
// negative values give 0.
std::uint64_t saturating_count(double x);

// Lattice sites that sample_lattice visits for bounds `b` at spacing dx: the per-axis counts
// (at least 1 each) multiplied, saturating.
std::uint64_t lattice_site_count(const Bounds& b, int dimension, double dx);

// Lattice offsets within the horizon (the family of an interior point), from the ball's volume
// in cells: pi m^2 (2D) or 4/3 pi m^3 (3D) for m = horizon / spacing, saturating. Within a few
// per cent of lattice_family_size for m >= 2 and cheap for any m (the exact count loops over
// (2m + 3)^d offsets: 1e12 for m = 1e4).
std::uint64_t family_size_estimate(int dimension, double horizon_ratio);

// Lower bound of a body's memory: per point its kinematic state and per-point constants, per
// bond its neighbour index, flag and reference data (bodies/body.hpp, bodies/bond_family.hpp).
inline constexpr std::uint64_t kBytesPerPoint = 256;
inline constexpr std::uint64_t kBytesPerBond = 32;
std::uint64_t body_bytes_estimate(std::uint64_t points, std::uint64_t family);

// The most lattice offsets a family may hold (horizon_ratio ~ 29 in 3D, ~ 178 in 2D): a larger
// family is no discretisation a peridynamic model is used with, and its set-up cost grows as
// the family's square or cube.
inline constexpr std::uint64_t kMaxFamilySize = 100'000;

// The budget bodies are refused against when the case gives no max_memory: MemAvailable from
// /proc/meminfo, or the value set here (the fuzz harness sets a small one). 0: unknown.
void set_default_memory_budget(std::uint64_t bytes);
std::uint64_t default_memory_budget();
// MemAvailable in bytes, or nullopt when /proc/meminfo cannot be read.
std::optional<std::uint64_t> machine_available_memory();

// "1.8e+19" style for counts that may be saturated ("over 1.8e+19" when saturated) and
// "12.3 GB" for bytes.
std::string format_count(std::uint64_t n);
std::string format_bytes(std::uint64_t bytes);

}  // namespace ckpd
