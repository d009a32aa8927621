#include "src/engine/halo.hpp"

#include <stdexcept>
#include <string>

namespace ckpd {

std::uint64_t HaloLinks::ghosts() const {
  std::uint64_t n = 0;
  for (const auto& r : receive) n += r.size();
  return n;
}

std::uint64_t HaloLinks::sent() const {
  std::uint64_t n = 0;
  for (const auto& s : send) n += s.size();
  return n;
}

int HaloLinks::neighbours() const {
  int n = 0;
  for (std::size_t q = 0; q < receive.size(); ++q) n += !receive[q].empty() || !send[q].empty();
  return n;
}

HaloLinks halo_links(const Body& body, const std::vector<int>& owner, int rank, int ranks) {
  const std::size_t n = body.size();
  if (owner.size() != n)
    throw std::invalid_argument("halo_links: body '" + body.name +
                                "': " + std::to_string(owner.size()) + " owners for " +
                                std::to_string(n) + " points");
  if (ranks < 1 || rank < 0 || rank >= ranks)
    throw std::invalid_argument("halo_links: rank " + std::to_string(rank) + " of " +
                                std::to_string(ranks));
  for (std::size_t i = 0; i < n; ++i)
    if (owner[i] < 0 || owner[i] >= ranks)
      throw std::invalid_argument("halo_links: body '" + body.name + "': point " +
                                  std::to_string(i) + " has owner " + std::to_string(owner[i]) +
                                  ", not a rank below " + std::to_string(ranks));
  const BondFamily& f = body.family;
  // Kept points: the owned ones and their family members (the halo is symmetric: j is in i's
  // family exactly when i is in j's).
  std::vector<std::uint8_t> keep(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (owner[i] != rank) continue;
    keep[i] = 1;
    for (std::size_t k = f.offset[i]; k < f.offset[i + 1]; ++k) keep[f.neighbour[k]] = 1;
  }
  HaloLinks links;
  const std::size_t R = static_cast<std::size_t>(ranks);
  links.receive.resize(R);
  links.send.resize(R);
  // Per rank q, the last own point appended to send[q] (each point once per rank, and in
  // increasing order because i increases).
  std::vector<std::int64_t> last_sent(R, -1);
  for (std::size_t i = 0; i < n; ++i) {
    if (keep[i] == 0) continue;
    const std::uint32_t local = static_cast<std::uint32_t>(links.points.size());
    links.points.push_back(static_cast<std::uint32_t>(i));
    const bool mine = owner[i] == rank;
    links.owned.push_back(mine ? 1 : 0);
    if (!mine) {
      links.receive[static_cast<std::size_t>(owner[i])].push_back(local);
      continue;
    }
    for (std::size_t k = f.offset[i]; k < f.offset[i + 1]; ++k) {
      const std::size_t q = static_cast<std::size_t>(owner[f.neighbour[k]]);
      if (q == static_cast<std::size_t>(rank) || last_sent[q] == static_cast<std::int64_t>(i))
        continue;
      last_sent[q] = static_cast<std::int64_t>(i);
      links.send[q].push_back(local);
    }
  }
  return links;
}

}  // namespace ckpd
