#include "src/cli/rank_agreement.hpp"

#include <array>
#include <cstring>
#include <vector>

#include "src/engine/ranks.hpp"
#include "src/sweep/run_key.hpp"

namespace ckpd {

namespace {

// FNV-1a over raw bytes, continuing from `h` (sweep::fnv1a's constants).
std::uint64_t hash_bytes(const void* data, std::size_t size, std::uint64_t h) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    h ^= p[i];
    h *= 1099511628211ull;
  }
  return h;
}

std::uint64_t points_digest(const Scene& scene) {
  std::uint64_t h = sweep::fnv1a("");
  for (const SceneBody& sb : scene.bodies) {
    const Body& b = sb.body;
    const std::uint64_t n = b.size();
    h = hash_bytes(&n, sizeof n, h);
    h = hash_bytes(b.reference_position.data(), b.reference_position.size() * sizeof(Vec3), h);
  }
  return h;
}

constexpr std::array<const char*, 3> kWhat{
    "the resolved case (the case file with its --set overrides)",
    "the bodies' points (a mesh or point-cloud file that differs between the nodes?)",
    "--out, --restart or --gather-output"};

}  // namespace

int agree_on_loaded_case(const LoadedCase& loaded) {
  const std::string options =
      loaded.out + '\n' + loaded.restart + '\n' + (loaded.gather_output ? "gather" : "share");
  const std::array<std::uint64_t, 3> digest{sweep::fnv1a(loaded.resolved_case),
                                            points_digest(*loaded.scene), sweep::fnv1a(options)};
  // Each 64-bit digest as two 32-bit halves: doubles carry them exactly.
  std::vector<double> mine, all;
  for (const std::uint64_t d : digest) {
    mine.push_back(static_cast<double>(d >> 32));
    mine.push_back(static_cast<double>(d & 0xffffffffu));
  }
  ranks::all_gather(mine, all);
  std::string message;
  for (std::size_t k = 0; k < kWhat.size() && message.empty(); ++k) {
    const std::size_t at = ranks::rank() * mine.size() + 2 * k;
    if (all[at] != all[2 * k] || all[at + 1] != all[2 * k + 1])
      message = "mpirun: rank " + std::to_string(ranks::rank()) + " of " +
                std::to_string(ranks::count()) + " did not load what rank 0 loaded: " + kWhat[k] +
                " differs from rank 0's; every rank of a run must run the same case with the same "
                "options";
  }
  return ranks::agree_on_failure(message.empty() ? 0 : 2, message);
}

}  // namespace ckpd
