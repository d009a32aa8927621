#pragma once
// The sets of one point's own family that the bonds failing now switch off (damage booking,
// bond_failure.hpp), enumerated from the failures themselves: each set that holds a failing
// bond of the centre (either damage rule) or, under DamageRule::all_edges, a failing edge
// between two of its members, visited once. The family's slots are FamilyScratch::load's
// (intact bonds, in row order, the same offsets bit for bit) and two slots are adjacent exactly
// when they are there; but an adjacency row is built only for a slot that a switching set
// needs, so a point whose family holds one failing edge costs O(family), not O(family^2) and a
// bond look-up per pair. A row is one vector loop of distance tests over the members' reference
// offsets (kept as three arrays for it) and, under all_edges, the failed bonds of that slot's
// CSR row taken out through a point-to-slot table (no merge of two sorted rows, whose branch
// mispredicted about every other entry).
#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

#include "bodies/body.hpp"
#include "bodies/flag_scan.hpp"

namespace ckpd {

class SwitchingFamily {
 public:
  // Loads point i's intact family and the failures in it: `failing` flags the stored bonds about
  // to fail, `ends` the points that hold one. With `edges` (all_edges and a body with sets) the
  // failing edges between two members are found from the members that are ends.
  void load(const Body& body, std::size_t i, const std::vector<std::uint8_t>& failing,
            const std::vector<std::uint8_t>& ends, bool edges) {
    body_ = &body;
    const std::size_t begin = body.family.offset[i], end = body.family.offset[i + 1];
    const bool has_u = !body.displacement.empty();
    const Vec3 Xi = body.reference_position[i], ui = has_u ? body.displacement[i] : Vec3::Zero();
    // The last point's slots out of the table (it is all zero between loads otherwise).
    for (std::size_t a = 0; a < size_; ++a) slot_of_[index[a]] = 0;
    size_ = 0;
    reserve(end - begin, body.size());
    for (std::size_t k = begin; k < end; ++k) {
      if (!body.bond_intact[k]) continue;
      const std::uint32_t j = body.family.neighbour[k];
      index[size_] = j;
      bond[size_] = k;
      ref[size_] = body.reference_position[j] - Xi;
      cur[size_] = has_u ? Vec3(ref[size_] + (body.displacement[j] - ui)) : ref[size_];
      ref_x_[size_] = ref[size_].x();
      ref_y_[size_] = ref[size_].y();
      ref_z_[size_] = ref[size_].z();
      slot_of_[j] = static_cast<std::uint32_t>(size_ + 1);
      ++size_;
    }
    words_ = (size_ + 63) / 64;
    const double limit = body.horizon * (1 + kHorizonTolerance);
    limit2_ = limit * limit;
    skip_failed_ = body.damage_rule == DamageRule::all_edges;
    clear(failing_slot_, 0, words_);
    clear(row_built_, 0, words_);
    clear(edge_member_, 0, words_);
    for (std::size_t a = 0; a < size_; ++a)
      if (failing[bond[a]]) set(failing_slot_, 0, a);
    if (!edges) return;
    // A failing edge b-c (b < c, both members, within the horizon of each other) is found in the
    // bond row of b; both ends of a failing bond are ends, so b's row is walked.
    for (std::size_t b = 0; b < size_; ++b) {
      const std::uint32_t j = index[b];
      if (!ends[j]) continue;
      for_each_flag_other_than(failing.data(), body.family.offset[j], body.family.offset[j + 1], 0,
                               [&](std::size_t p) {
                                 const std::uint32_t c = slot_of_[body.family.neighbour[p]];
                                 if (c == 0 || c - 1 <= b || !within(b, c - 1)) return;
                                 add_edge(b, c - 1);
                                 add_edge(c - 1, b);
                               });
    }
  }

  bool slot_failing(std::size_t a) const { return test(failing_slot_, 0, a); }

  // f(a) for every slot whose own bond fails now.
  template <class SlotFn>
  void for_each_failing_slot(SlotFn&& f) const {
    for (std::size_t w = 0; w < words_; ++w)
      for (std::uint64_t bits = failing_slot_[w]; bits; bits &= bits - 1)
        f(w * 64 + static_cast<std::size_t>(std::countr_zero(bits)));
  }

  // f(a, b), a < b, for every adjacent pair that the failures switch off, each once: from its
  // smallest failing slot, else from its failing edge.
  template <class PairFn>
  void for_each_switching_pair(PairFn&& f) {
    for_each_failing_slot([&](std::size_t a) {
      const std::uint64_t* ra = row(a);
      for (std::size_t w = 0; w < words_; ++w)
        for (std::uint64_t bits = ra[w]; bits; bits &= bits - 1) {
          const std::size_t b = w * 64 + static_cast<std::size_t>(std::countr_zero(bits));
          if (b < a && slot_failing(b)) continue;
          f(std::min(a, b), std::max(a, b));
        }
    });
    for_each_failing_edge([&](std::size_t b, std::size_t c) {
      if (!slot_failing(b) && !slot_failing(c)) f(b, c);
    });
  }

  // f(a, b, c), a < b < c, for every pairwise-adjacent triple that the failures switch off, each
  // once: from its smallest failing slot, else from its smallest failing edge.
  template <class TripleFn>
  void for_each_switching_triple(TripleFn&& f) {
    for_each_failing_slot([&](std::size_t a) {
      const std::uint64_t* ra = row(a);
      for (std::size_t w = 0; w < words_; ++w)
        for (std::uint64_t bits = ra[w]; bits; bits &= bits - 1) {
          const std::size_t y = w * 64 + static_cast<std::size_t>(std::countr_zero(bits));
          if (y < a && slot_failing(y)) continue;
          const std::uint64_t* ry = row(y);
          for (std::size_t v = y / 64; v < words_; ++v) {
            std::uint64_t common = ra[v] & ry[v] & above(y, v);
            // z < a failing: the triple is booked from z.
            if (v <= a / 64) common &= ~(failing_slot_[v] & below(a, v));
            for (; common; common &= common - 1) {
              const std::size_t z = v * 64 + static_cast<std::size_t>(std::countr_zero(common));
              sorted(a, y, z, f);
            }
          }
        }
    });
    for_each_failing_edge([&](std::size_t b, std::size_t c) {
      if (slot_failing(b) || slot_failing(c)) return;
      const std::uint64_t* rb = row(b);
      const std::uint64_t* rc = row(c);
      for (std::size_t w = 0; w < words_; ++w) {
        std::uint64_t common = rb[w] & rc[w] & ~failing_slot_[w];
        for (; common; common &= common - 1) {
          const std::size_t z = w * 64 + static_cast<std::size_t>(std::countr_zero(common));
          // Booked from the triple's smallest failing edge, (lower slot, higher slot) in
          // lexicographic order; b-c is one of them.
          if (failing_edge(b, z) && before(b, z, b, c)) continue;
          if (failing_edge(c, z) && before(c, z, b, c)) continue;
          sorted(b, c, z, f);
        }
      }
    });
  }

  // f(b, c), b < c, for every failing edge between two members (all_edges).
  template <class EdgeFn>
  void for_each_failing_edge(EdgeFn&& f) const {
    for (std::size_t v = 0; v < words_; ++v)
      for (std::uint64_t members = edge_member_[v]; members; members &= members - 1) {
        const std::size_t b = v * 64 + static_cast<std::size_t>(std::countr_zero(members));
        for (std::size_t w = b / 64; w < words_; ++w)
          for (std::uint64_t bits = edge_[b * words_ + w] & above(b, w); bits; bits &= bits - 1)
            f(b, w * 64 + static_cast<std::size_t>(std::countr_zero(bits)));
      }
  }

  std::size_t size() const { return size_; }
  // Makes room for families of up to n members of a body of `points` points now, so that later
  // loads allocate nothing.
  void reserve(std::size_t n, std::size_t points) {
    grow(n);
    if (slot_of_.size() < points) slot_of_.resize(points, 0);
  }

  std::vector<Vec3> ref, cur;
  std::vector<std::uint32_t> index;  // each slot's point
  std::vector<std::size_t> bond;     // each slot's bond: its position in the body's CSR rows

 private:
  static void clear(std::vector<std::uint64_t>& v, std::size_t from, std::size_t count) {
    std::fill(v.begin() + static_cast<std::ptrdiff_t>(from),
              v.begin() + static_cast<std::ptrdiff_t>(from + count), 0);
  }
  static void set(std::vector<std::uint64_t>& v, std::size_t from, std::size_t a) {
    v[from + a / 64] |= std::uint64_t{1} << (a % 64);
  }
  static bool test(const std::vector<std::uint64_t>& v, std::size_t from, std::size_t a) {
    return (v[from + a / 64] >> (a % 64)) & 1;
  }
  // Mask of the bits of word w whose slot index is > s (< s).
  static std::uint64_t above(std::size_t s, std::size_t w) {
    if (s / 64 < w) return ~std::uint64_t{0};
    if (s / 64 > w) return 0;
    const std::size_t bit = s % 64;
    return bit == 63 ? 0 : (~std::uint64_t{0} << (bit + 1));
  }
  static std::uint64_t below(std::size_t s, std::size_t w) {
    if (s / 64 > w) return ~std::uint64_t{0};
    if (s / 64 < w) return 0;
    return (std::uint64_t{1} << (s % 64)) - 1;
  }
  // Edge (p, q) before edge (r, s) in lexicographic order of (lower, higher) slot.
  static bool before(std::size_t p, std::size_t q, std::size_t r, std::size_t s) {
    const std::size_t p0 = std::min(p, q), p1 = std::max(p, q);
    return p0 < r || (p0 == r && p1 < s);
  }
  template <class TripleFn>
  static void sorted(std::size_t a, std::size_t b, std::size_t c, TripleFn& f) {
    if (a > b) std::swap(a, b);
    if (b > c) std::swap(b, c);
    if (a > b) std::swap(a, b);
    f(a, b, c);
  }

  // FamilyScratch::load's adjacency test: within the horizon (the same offsets, the same
  // rounding: Eigen's squaredNorm of a 3-vector is (x x + y y) + z z) and, under all_edges, the
  // bond between the two not failed before this step.
  bool within(std::size_t a, std::size_t b) const {
    return (ref[b] - ref[a]).squaredNorm() <= limit2_;
  }
  // Slot a's adjacency row, built on first use.
  const std::uint64_t* row(std::size_t a) {
    std::uint64_t* r = &adjacency_[a * words_];
    if (test(row_built_, 0, a)) return r;
    set(row_built_, 0, a);
    const double xa = ref_x_[a], ya = ref_y_[a], za = ref_z_[a];
    for (std::size_t w = 0; w < words_; ++w) {
      const std::size_t first = w * 64, last = std::min(first + 64, size_);
      std::uint64_t bits = 0;
      for (std::size_t b = first; b < last; ++b) {
        const double dx = ref_x_[b] - xa, dy = ref_y_[b] - ya, dz = ref_z_[b] - za;
        bits |= std::uint64_t{(dx * dx + dy * dy) + dz * dz <= limit2_} << (b - first);
      }
      r[w] = bits;
    }
    r[a / 64] &= ~(std::uint64_t{1} << (a % 64));
    if (skip_failed_) {
      const Body& body = *body_;
      const std::uint32_t j = index[a];
      for_each_flag_other_than(body.bond_intact.data(), body.family.offset[j],
                               body.family.offset[j + 1], 1, [&](std::size_t p) {
                                 if (const std::uint32_t c = slot_of_[body.family.neighbour[p]])
                                   r[(c - 1) / 64] &= ~(std::uint64_t{1} << ((c - 1) % 64));
                               });
    }
    return r;
  }
  void add_edge(std::size_t b, std::size_t c) {
    if (!test(edge_member_, 0, b)) {
      set(edge_member_, 0, b);
      clear(edge_, b * words_, words_);
    }
    set(edge_, b * words_, c);
  }
  bool failing_edge(std::size_t b, std::size_t c) const {
    return test(edge_member_, 0, b) && test(edge_, b * words_, c);
  }
  void grow(std::size_t n) {
    if (ref.size() < n) {
      ref.resize(n);
      cur.resize(n);
      index.resize(n);
      bond.resize(n);
      ref_x_.resize(n);
      ref_y_.resize(n);
      ref_z_.resize(n);
    }
    const std::size_t w = (n + 63) / 64;
    if (adjacency_.size() < n * w) {
      adjacency_.resize(n * w);
      edge_.resize(n * w);
    }
    if (failing_slot_.size() < w) {
      failing_slot_.resize(w);
      row_built_.resize(w);
      edge_member_.resize(w);
    }
  }

  const Body* body_ = nullptr;
  std::size_t size_ = 0, words_ = 0;
  double limit2_ = 0;
  bool skip_failed_ = false;
  std::vector<std::uint64_t> adjacency_, edge_;  // one bit row per slot
  std::vector<std::uint64_t> failing_slot_, row_built_, edge_member_;
  std::vector<double> ref_x_, ref_y_, ref_z_;  // ref by component, for the row's vector loop
  // Each point's slot + 1 in the loaded family, 0 for the others: one entry per point of the
  // body, cleared member by member at the next load.
  std::vector<std::uint32_t> slot_of_;
};

}  // namespace ckpd
