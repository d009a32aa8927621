#include "bodies/fragments.hpp"

#include <numeric>

namespace ckpd {

namespace {
std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];  // path halving
    i = parent[i];
  }
  return i;
}
}  // namespace

std::size_t FragmentCensus::count_at_least(std::size_t min_points) const {
  std::size_t n = 0;
  for (std::size_t s : size) n += s >= min_points;
  return n;
}

FragmentCensus find_fragments(const Body& body) {
  const std::size_t n = body.size();
  std::vector<std::uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k) {
      if (!body.bond_intact[k]) continue;
      const std::uint32_t a = find_root(parent, static_cast<std::uint32_t>(i));
      const std::uint32_t b = find_root(parent, body.family.neighbour[k]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  FragmentCensus census;
  census.label.assign(n, 0);
  std::vector<std::uint32_t> id(n, UINT32_MAX);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t r = find_root(parent, static_cast<std::uint32_t>(i));
    if (id[r] == UINT32_MAX) {
      id[r] = static_cast<std::uint32_t>(census.size.size());
      census.size.push_back(0);
    }
    census.label[i] = id[r];
    ++census.size[id[r]];
  }
  return census;
}

}  // namespace ckpd
