#include "bodies/operator_classes.hpp"

#include <algorithm>
#include <bit>
#include <cstdlib>
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
    values(r, visit);
  }
  // The bits of member r's volume and effective volumes.
  template <class Visit>
  void values(std::uint32_t r, Visit&& visit) const {
    visit(std::bit_cast<std::uint64_t>(body.volume[r]));
    for (const std::vector<double>* dv : {&body.dv1, &body.dv2, &body.dv3})
      if (!dv->empty()) visit(std::bit_cast<std::uint64_t>((*dv)[r]));
  }
  bool same_values(std::uint32_t r, std::uint32_t q) const {
    std::uint64_t wr[4], wq[4];
    int nr = 0, nq = 0;
    values(r, [&](std::uint64_t w) { wr[nr++] = w; });
    values(q, [&](std::uint64_t w) { wq[nq++] = w; });
    return nr == nq && std::memcmp(wr, wq, sizeof(std::uint64_t) * nr) == 0;
  }
  std::array<std::int64_t, 3> offset(std::size_t i, std::uint32_t r) const {
    return {std::int64_t{coord[3 * r]} - coord[3 * i],
            std::int64_t{coord[3 * r + 1]} - coord[3 * i + 1],
            std::int64_t{coord[3 * r + 2]} - coord[3 * i + 2]};
  }
  // A hash of row i's members that every lattice symmetry leaves alone: per member its sorted
  // absolute offsets and its values, summed (the members' order changes under a symmetry).
  std::uint64_t symmetric_hash(std::size_t i) const {
    std::uint64_t sum = 0;
    for (std::size_t a = 0; a < members(i); ++a) {
      const std::uint32_t r = member(i, a);
      std::array<std::int64_t, 3> o = offset(i, r);
      for (std::int64_t& x : o) x = std::abs(x);
      std::sort(o.begin(), o.end());
      std::uint64_t h = 0;
      for (std::int64_t x : o) h = mix(h, static_cast<std::uint64_t>(x));
      values(r, [&](std::uint64_t w) { h = mix(h, w); });
      sum += h;
    }
    return mix(members(i), sum);
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

// Row i's members' first and second moments of their offsets (sum o, sum o o^T: xx, yy, zz, xy,
// xz, yz): a symmetry that maps r's members onto p's maps r's moments onto p's.
struct Moments {
  std::array<std::int64_t, 3> first{};
  std::array<std::int64_t, 6> second{};
};

Moments moments(const RowKey& key, std::size_t i) {
  Moments m;
  for (std::size_t a = 1; a < key.members(i); ++a) {
    const std::array<std::int64_t, 3> o = key.offset(i, key.member(i, a));
    for (int d = 0; d < 3; ++d) m.first[d] += o[d];
    m.second[0] += o[0] * o[0];
    m.second[1] += o[1] * o[1];
    m.second[2] += o[2] * o[2];
    m.second[3] += o[0] * o[1];
    m.second[4] += o[0] * o[2];
    m.second[5] += o[1] * o[2];
  }
  return m;
}

// Whether S maps moments r onto moments p.
bool maps_moments(const LatticeSymmetry& S, const Moments& r, const Moments& p) {
  for (int d = 0; d < 3; ++d)
    if (S.sign[d] * r.first[S.perm[d]] != p.first[d]) return false;
  // (S M S^T)(a, b) = sign[a] sign[b] M(perm[a], perm[b]).
  auto second = [](const Moments& m, int a, int b) {
    if (a == b) return m.second[a];
    if (a > b) std::swap(a, b);
    return m.second[a == 0 ? (b == 1 ? 3 : 4) : 5];
  };
  for (int a = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b)
      if (S.sign[a] * S.sign[b] * second(r, S.perm[a], S.perm[b]) != second(p, a, b)) return false;
  return true;
}

// Row p's members into (fill) and out of (clear) the table.
void fill(OffsetTable& table, const RowKey& key, std::size_t p) {
  for (std::size_t a = 0; a < key.members(p); ++a)
    table.set(key.offset(p, key.member(p, a)), static_cast<std::int32_t>(a));
}
void clear(OffsetTable& table, const RowKey& key, std::size_t p) {
  for (std::size_t a = 0; a < key.members(p); ++a) table.set(key.offset(p, key.member(p, a)), -1);
}

// Whether p's members are S times r's, member by member with the same values (p's table filled).
bool is_image(const RowKey& key, const LatticeSymmetry& S, std::size_t r, std::size_t p,
              const OffsetTable& table_p) {
  if (key.members(r) != key.members(p)) return false;
  for (std::size_t a = 0; a < key.members(r); ++a) {
    const std::uint32_t q = key.member(r, a);
    const std::array<std::int64_t, 3> o = key.offset(r, q);
    const std::int32_t slot =
        table_p.at({S.sign[0] * o[S.perm[0]], S.sign[1] * o[S.perm[1]], S.sign[2] * o[S.perm[2]]});
    if (slot < 0 || !key.same_values(q, key.member(p, static_cast<std::size_t>(slot))))
      return false;
  }
  return true;
}

}  // namespace

const std::array<LatticeSymmetry, 48>& lattice_symmetries() {
  // The permutations keeping z first, so that the first 8 are the plane's symmetries.
  static const std::array<LatticeSymmetry, 48> all = [] {
    std::array<LatticeSymmetry, 48> out{};
    const int perms[6][3] = {{0, 1, 2}, {1, 0, 2}, {0, 2, 1}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    std::size_t k = 0;
    for (const auto& perm : perms)
      for (int z : {1, -1})
        for (int y : {1, -1})
          for (int x : {1, -1}) {
            out[k].perm = {perm[0], perm[1], perm[2]};
            out[k].sign = {x, y, z};
            ++k;
          }
    // Keep-z permutations with sign z = +1 first: perms {0,1,2} and {1,0,2}, z = 1.
    std::stable_partition(out.begin(), out.end(), [](const LatticeSymmetry& S) {
      return S.perm[2] == 2 && S.sign[2] == 1;
    });
    return out;
  }();
  return all;
}

RowClasses operator_row_classes(const Body& body) {
  const std::size_t n = body.size();
  RowClasses out;
  std::vector<std::uint32_t>& first = out.first;
  first.resize(n);
  for (std::size_t i = 0; i < n; ++i) first[i] = static_cast<std::uint32_t>(i);
  out.source = first;
  out.symmetry.assign(n, 0);
  LatticeCoordinates lattice = lattice_coordinates(body);
  if (lattice.coord.empty()) return out;
  out.coord = std::move(lattice.coord);
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
  const RowKey key{body, out.coord};
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
  std::vector<std::uint32_t> classes;  // first points, in point order
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
    if (!found) {
      candidates.push_back(static_cast<std::uint32_t>(i));
      classes.push_back(static_cast<std::uint32_t>(i));
    }
  }
  // Orbits of the classes under the lattice's symmetries, in point order as well: a class is
  // turned from the first earlier orbit's class that some symmetry maps onto it, trying the
  // symmetries in lattice_symmetries()'s order (the identity first: two classes whose members
  // differ only in their order).
  std::vector<std::uint64_t> symmetric(classes.size());
  std::vector<Moments> moment(classes.size());
  std::int64_t reach = 0;
#pragma omp parallel for schedule(dynamic, 16) reduction(max : reach)
  for (std::size_t c = 0; c < classes.size(); ++c) {
    symmetric[c] = key.symmetric_hash(classes[c]);
    moment[c] = moments(key, classes[c]);
    for (std::size_t a = 1; a < key.members(classes[c]); ++a)
      for (std::int64_t x : key.offset(classes[c], key.member(classes[c], a)))
        reach = std::max(reach, std::abs(x));
  }
  // The offset table's cube grows like the horizon in spacings cubed: past 2^24 cells (a
  // horizon of some 128 spacings) the classes are each assembled.
  if (2 * reach + 1 > 256) return out;
  out.reach = reach;
  const std::size_t symmetries = lattice_symmetry_count(body.dimension);
  OffsetTable table(reach);
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> orbits;  // by symmetric hash
  for (std::size_t c = 0; c < classes.size(); ++c) {
    const std::uint32_t p = classes[c];
    std::vector<std::size_t>& candidates = orbits[symmetric[c]];
    bool found = false;
    fill(table, key, p);
    for (std::size_t r : candidates) {
      for (std::size_t s = 0; s < symmetries && !found; ++s) {
        const LatticeSymmetry& S = lattice_symmetries()[s];
        if (!maps_moments(S, moment[r], moment[c]) || !is_image(key, S, classes[r], p, table))
          continue;
        out.source[p] = classes[r];
        out.symmetry[p] = static_cast<std::uint8_t>(s);
        found = true;
      }
      if (found) break;
    }
    clear(table, key, p);
    if (!found) candidates.push_back(c);
  }
  return out;
}

}  // namespace ckpd
