#include "bodies/operator_classes.hpp"

#include <bit>
#include <cstring>
#include <unordered_map>

#include "bodies/body.hpp"
#include "bodies/lattice_stencil.hpp"

namespace ckpd {

namespace {

std::uint64_t mix(std::uint64_t h, std::uint64_t v) {
  // splitmix64's finaliser over the running hash and the next word.
  std::uint64_t x = h ^ (v + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2));
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// What row i reads, point by point over {i} and i's family in row order.
struct RowKey {
  const Body& body;
  const std::vector<std::int32_t>& coord;

  std::uint32_t member(std::size_t i, std::size_t slot) const {
    return slot == 0 ? static_cast<std::uint32_t>(i)
                     : body.family.neighbour[body.family.offset[i] + slot - 1];
  }
  std::size_t members(std::size_t i) const { return 1 + body.family.family_size(i); }
  // The words of one member r of row i: its offset from i and its volumes' bits.
  template <class Visit>
  void words(std::size_t i, std::uint32_t r, Visit&& visit) const {
    for (int d = 0; d < 3; ++d)
      visit(static_cast<std::uint64_t>(static_cast<std::int64_t>(coord[3 * r + d]) -
                                       coord[3 * i + d]));
    visit(std::bit_cast<std::uint64_t>(body.volume[r]));
    for (const std::vector<double>* dv : {&body.dv1, &body.dv2, &body.dv3})
      if (!dv->empty()) visit(std::bit_cast<std::uint64_t>((*dv)[r]));
  }
  std::uint64_t hash(std::size_t i) const {
    std::uint64_t h = members(i);
    for (std::size_t a = 0; a < members(i); ++a)
      words(i, member(i, a), [&](std::uint64_t w) { h = mix(h, w); });
    return h;
  }
  bool same(std::size_t i, std::size_t j) const {
    if (members(i) != members(j)) return false;
    for (std::size_t a = 0; a < members(i); ++a) {
      std::uint64_t wi[8], wj[8];
      int ni = 0, nj = 0;
      words(i, member(i, a), [&](std::uint64_t w) { wi[ni++] = w; });
      words(j, member(j, a), [&](std::uint64_t w) { wj[nj++] = w; });
      if (ni != nj || std::memcmp(wi, wj, sizeof(std::uint64_t) * ni) != 0) return false;
    }
    return true;
  }
};

}  // namespace

std::vector<std::uint32_t> operator_row_classes(const Body& body) {
  const std::size_t n = body.size();
  std::vector<std::uint32_t> first(n);
  for (std::size_t i = 0; i < n; ++i) first[i] = static_cast<std::uint32_t>(i);
  const LatticeCoordinates lattice = lattice_coordinates(body);
  if (lattice.coord.empty()) return first;
  // intact[i]: every bond of i intact (a point whose members all are can be classed).
  std::vector<std::uint8_t> intact(n, 1);
  if (!body.bond_intact.empty()) {
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k)
        if (!body.bond_intact[k]) {
          intact[i] = 0;
          break;
        }
  }
  const RowKey key{body, lattice.coord};
  std::vector<std::uint64_t> hash(n, 0);
  std::vector<std::uint8_t> classable(n, 0);
#pragma omp parallel for schedule(dynamic, 64)
  for (std::size_t i = 0; i < n; ++i) {
    bool clean = intact[i] != 0;
    for (std::size_t k = body.family.offset[i]; clean && k < body.family.offset[i + 1]; ++k)
      clean = intact[body.family.neighbour[k]] != 0;
    if (!clean) continue;
    classable[i] = 1;
    hash[i] = key.hash(i);
  }
  // In point order, so that a class's first point is its smallest and the result does not
  // depend on the thread count. Equal hashes are confirmed by comparing the keys in full.
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> by_hash;
  for (std::size_t i = 0; i < n; ++i) {
    if (!classable[i]) continue;
    std::vector<std::uint32_t>& candidates = by_hash[hash[i]];
    bool found = false;
    for (std::uint32_t c : candidates)
      if (key.same(i, c)) {
        first[i] = c;
        found = true;
        break;
      }
    if (!found) candidates.push_back(static_cast<std::uint32_t>(i));
  }
  return first;
}

}  // namespace ckpd
