#include "src/sweep/run_key.hpp"

#include <cstdio>

namespace ckpd::sweep {

std::uint64_t fnv1a(const std::string& text, std::uint64_t h) {
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

std::string hex16(std::uint64_t h) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

std::string run_key(const YAML::Node& resolved_case) {
  YAML::Node physics;
  for (const auto& kv : resolved_case)
    if (kv.first.as<std::string>() != "description") physics[kv.first] = kv.second;
  return hex16(fnv1a(YAML::Dump(physics), fnv1a(kPhysicsVersion)));
}

}  // namespace ckpd::sweep
