#pragma once
// The key of a run: what decides its results. A resumed sweep skips a run whose folder holds a
// completed summary under the same key.
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <string>

namespace ckpd::sweep {

// Bump when a change to ckpd changes the results of an unchanged case: it invalidates every
// finished run of earlier sweeps.
inline constexpr const char* kPhysicsVersion = "ckpd-physics-1";

std::uint64_t fnv1a(const std::string& text, std::uint64_t h = 14695981039346656037ull);
std::string hex16(std::uint64_t h);

// Hash of the resolved case (the base case with the run's overrides applied, re-emitted so that
// comments and layout do not count; `description` left out) and kPhysicsVersion. Files a case
// refers to (point clouds) enter by name only. The thread count does not enter: it changes
// results in the last bits only.
std::string run_key(const YAML::Node& resolved_case);

}  // namespace ckpd::sweep
