#pragma once
// Enumerates the two- and three-neighbour sets of one point on the fly from its bond family
// (THEORY.md section 2): unordered pairs a < b and triples a < b < c of family slots whose
// members are pairwise within the horizon. Adjacency between slots is kept as bit rows so the
// triple candidates of a pair are one AND of two rows. One scratch per thread; it only grows.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

#include "bodies/body.hpp"

namespace ckpd {

class FamilyScratch {
 public:
  // Loads point i's family: reference offsets dX, current offsets dx = dX + (u_j - u_i)
  // (added in this order so that small displacements keep their precision), reference lengths
  // and, when `pairs_needed`, the adjacency rows. With `intact_only`, failed bonds are left out;
  // under DamageRule::all_edges, so is the adjacency of two slots whose own bond has failed,
  // which leaves out every triangle and tetrahedron with a failed edge.
  void load(const Body& body, std::size_t i, bool intact_only, bool pairs_needed) {
    const std::size_t begin = body.family.offset[i], end = body.family.offset[i + 1];
    const Vec3 Xi = body.reference_position[i],
               ui = body.displacement.empty() ? Vec3::Zero() : body.displacement[i];
    const bool has_u = !body.displacement.empty();
    size_ = 0;
    grow(end - begin);
    for (std::size_t k = begin; k < end; ++k) {
      if (intact_only && !body.bond_intact[k]) continue;
      const std::uint32_t j = body.family.neighbour[k];
      index[size_] = j;
      bond[size_] = k;
      ref[size_] = body.reference_position[j] - Xi;
      cur[size_] = has_u ? Vec3(ref[size_] + (body.displacement[j] - ui)) : ref[size_];
      length[size_] = ref[size_].norm();
      ++size_;
    }
    words_ = (size_ + 63) / 64;
    if (!pairs_needed) return;
    const double limit = body.horizon * (1 + kHorizonTolerance);
    const double limit2 = limit * limit;
    std::fill(adjacency.begin(), adjacency.begin() + static_cast<std::ptrdiff_t>(size_ * words_),
              0);
    const bool edges_intact = intact_only && body.damage_rule == DamageRule::all_edges;
    for (std::size_t a = 0; a < size_; ++a) {
      for (std::size_t b = a + 1; b < size_; ++b) {
        if ((ref[b] - ref[a]).squaredNorm() <= limit2 &&
            (!edges_intact || !bond_failed(body, index[a], index[b]))) {
          adjacency[a * words_ + b / 64] |= std::uint64_t{1} << (b % 64);
          adjacency[b * words_ + a / 64] |= std::uint64_t{1} << (a % 64);
        }
      }
    }
  }

  std::size_t size() const { return size_; }
  // Makes room for families of up to n members now, so that later loads allocate nothing.
  void reserve(std::size_t n) { grow(n); }

  // f(a, b) for every unordered adjacent pair a < b.
  template <class PairFn>
  void for_each_pair(PairFn&& f) const {
    for (std::size_t a = 0; a < size_; ++a) {
      const std::uint64_t* row = &adjacency[a * words_];
      for (std::size_t w = (a + 1) / 64; w < words_; ++w) {
        std::uint64_t bits = row[w] & above(a, w);
        while (bits) {
          const std::size_t b = w * 64 + static_cast<std::size_t>(std::countr_zero(bits));
          bits &= bits - 1;
          f(a, b);
        }
      }
    }
  }

  // f(a, b, c) for every unordered pairwise-adjacent triple a < b < c.
  template <class TripleFn>
  void for_each_triple(TripleFn&& f) const {
    for_each_pair([&](std::size_t a, std::size_t b) {
      for (std::size_t w = (b + 1) / 64; w < words_; ++w) {
        std::uint64_t bits = thirds_word(a, b, w);
        while (bits) {
          const std::size_t c = w * 64 + static_cast<std::size_t>(std::countr_zero(bits));
          bits &= bits - 1;
          f(a, b, c);
        }
      }
    });
  }

  // f(a, b, thirds, n) for every unordered adjacent pair a < b, with thirds[0..n) every c > b
  // adjacent to both (the triples of for_each_triple, a pair's at once for a vector loop over
  // c). thirds needs room for size() entries.
  template <class PairFn>
  void for_each_pair_with_thirds(std::uint32_t* thirds, PairFn&& f) const {
    for_each_pair([&](std::size_t a, std::size_t b) {
      std::size_t n = 0;
      for (std::size_t w = (b + 1) / 64; w < words_; ++w) {
        std::uint64_t bits = thirds_word(a, b, w);
        while (bits) {
          thirds[n++] = static_cast<std::uint32_t>(w * 64 + std::countr_zero(bits));
          bits &= bits - 1;
        }
      }
      f(a, b, static_cast<const std::uint32_t*>(thirds), n);
    });
  }

  // Marks third[d] = 1 for every d > b adjacent to both a and b (the triples (a, b, d) of
  // for_each_triple), 0 for the other d > b; whether there is any.
  template <class Flag>
  bool pair_thirds(std::size_t a, std::size_t b, Flag* third) const {
    std::uint64_t any = 0;
    for (std::size_t w = (b + 1) / 64; w < words_; ++w) {
      const std::uint64_t bits = thirds_word(a, b, w);
      any |= bits;
      const std::size_t first = std::max(w * 64, b + 1), last = std::min(w * 64 + 64, size_);
      for (std::size_t d = first; d < last; ++d)
        third[d] = static_cast<Flag>((bits >> (d % 64)) & 1);
    }
    return any != 0;
  }

  std::vector<Vec3> ref, cur;
  std::vector<double> length;
  std::vector<std::uint32_t> index;  // each slot's point
  std::vector<std::size_t> bond;     // each slot's bond: its position in the body's CSR rows

  static constexpr std::size_t kNoBond = ~std::size_t{0};
  // The position of bond j-k in j's sorted CSR row, kNoBond where j and k are not bonded.
  static std::size_t bond_position(const Body& body, std::uint32_t j, std::uint32_t k) {
    const auto begin =
        body.family.neighbour.begin() + static_cast<std::ptrdiff_t>(body.family.offset[j]);
    const auto end =
        body.family.neighbour.begin() + static_cast<std::ptrdiff_t>(body.family.offset[j + 1]);
    const auto it = std::lower_bound(begin, end, k);
    return it != end && *it == k ? static_cast<std::size_t>(it - body.family.neighbour.begin())
                                 : kNoBond;
  }

 private:
  // Whether j and k are bonded and that bond has failed.
  static bool bond_failed(const Body& body, std::uint32_t j, std::uint32_t k) {
    const std::size_t p = bond_position(body, j, k);
    return p != kNoBond && !body.bond_intact[p];
  }
  // Mask of the bits of word w whose slot index is > s.
  // Word w of the thirds of pair a < b: the slots c > b adjacent to both.
  std::uint64_t thirds_word(std::size_t a, std::size_t b, std::size_t w) const {
    return adjacency[a * words_ + w] & adjacency[b * words_ + w] & above(b, w);
  }
  static std::uint64_t above(std::size_t s, std::size_t w) {
    if (s / 64 < w) return ~std::uint64_t{0};
    const std::size_t bit = s % 64;
    return bit == 63 ? 0 : (~std::uint64_t{0} << (bit + 1));
  }
  void grow(std::size_t n) {
    if (ref.size() < n) {
      ref.resize(n);
      cur.resize(n);
      index.resize(n);
      bond.resize(n);
      length.resize(n);
    }
    const std::size_t w = (n + 63) / 64;
    if (adjacency.size() < n * w) adjacency.resize(n * w);
  }

  std::size_t size_ = 0, words_ = 0;
  std::vector<std::uint64_t> adjacency;
};

}  // namespace ckpd
