#pragma once
// The lattice stencil (issue 5): on a body sampled on a regular square or cubic lattice, every
// point's family is the same set of lattice offsets, minus those whose site is outside the body.
// The stencil holds, once per body, what the general kernel recomputes for every point in every
// step: which offsets are neighbours of each other, the reference lengths (1/L), the reference
// area of every pair of offsets (1/|A|) and the signed reference volume of every triple (1/V),
// from exact integer geometry. The symmetric kernel then evaluates a lattice point's sets with
// one table look-up in place of the reference cross products, triple products and divisions.
//
// Only the "upper" half of the offsets is kept (lexicographically positive in (z, y, x)): the
// symmetric kernel enumerates each set from its smallest-index vertex, and on a lattice whose
// points are numbered in (z, y, x) order, neighbours with larger index are exactly those at
// upper offsets, in the same order.
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace ckpd {

struct Body;

// The stencil's tables grow like m^9 (its triples); above this many bytes the body keeps the
// general path, which stores nothing per set. Measured (docs/PERFORMANCE.md): tables of 0.25 to
// 1.6 MB gain 1.05-1.34x; the seed's two-layer disc at m = 8 (10.2 MB) gained nothing with
// the scalar kernel (25.6 against 25.3 s per step) but 1.14-1.19x with the grouped tetrahedra,
// which read a pair's triple row and no per-triple table (6.9 against 7.8-8.2 s per step).
inline constexpr std::size_t kStencilMemoryLimit = std::size_t{32} << 20;

struct LatticeStencil {
  double spacing = 0;
  int reach = 0;            // the largest offset component
  std::size_t slots = 0;    // upper offsets
  std::size_t words = 0;    // 64-bit words per bit row over the slots
  std::size_t pairs = 0;    // adjacent slot pairs (a < b)
  std::size_t triples = 0;  // non-degenerate pairwise-adjacent slot triples (a < b < c)

  // Per point: integer lattice coordinates x, y, z (z = 0 in 2D).
  std::vector<std::int32_t> coord;
  // (2 reach + 1)^3 table over offsets: the upper slot, or -1.
  std::vector<std::int32_t> slot_table;
  std::vector<std::array<int, 3>> offset;  // per slot, in increasing (z, y, x) order
  std::vector<double> inv_length;          // per slot: 1 / L
  std::vector<double> length;              // per slot: L
  // slots x words: row a holds the slots b > a whose offset from a is within the horizon.
  std::vector<std::uint64_t> adjacency;
  // slots x words: row a holds the upper slots s whose offset added to a's, offset[a] +
  // offset[s], is a slot too (then it is one of row a's adjacency slots: with a fixed offset
  // added the (z, y, x) order stays, so the k-th slot of sum_inside row a lands on the k-th of
  // adjacency row a). A neighbour at upper slot s of the point at slot a is the centre's
  // neighbour exactly when s is in row a.
  std::vector<std::uint64_t> sum_inside;
  // Pairs are numbered slot by slot: pair (a, b) is pair_base[a] + (rank of b in row a).
  std::vector<std::uint32_t> pair_base;
  // Per pair, with the two-neighbour family: 1 / |A| of the reference area vector P x Q of the
  // two offsets (0: degenerate, left out) and its z component (the orientation of 2D sets).
  std::vector<double> inv_area, area_z;
  // With the three-neighbour family, per pair: a row (words) of the slots c > b adjacent to a
  // and b whose tetrahedron {0, a, b, c} is not degenerate, and the number of the first of those
  // triples; triple (a, b, c) is triple_base[pair] + (rank of c in that row). Per triple:
  // 1 / V of the signed reference volume P . (Q x R).
  std::vector<std::uint64_t> triple_row;
  std::vector<std::uint32_t> triple_base;
  std::vector<double> inv_volume;

  // The upper slot of neighbour j of point i (j > i and bonded to i).
  int slot(std::size_t i, std::size_t j) const {
    const std::int32_t* a = &coord[3 * i];
    const std::int32_t* b = &coord[3 * j];
    const int side = 2 * reach + 1;
    return slot_table[static_cast<std::size_t>(
        ((b[2] - a[2] + reach) * side + b[1] - a[1] + reach) * side + b[0] - a[0] + reach)];
  }
  // The upper slot of offset[a] + offset[s]: where the neighbour at upper slot s of the point
  // at upper slot a sits from the centre; -1 when that offset is no stencil offset (no neighbour
  // of the centre).
  int sum_slot(std::size_t a, std::size_t s) const {
    const std::array<int, 3>& p = offset[a];
    const std::array<int, 3>& q = offset[s];
    const int x = p[0] + q[0], y = p[1] + q[1], z = p[2] + q[2];
    if (x < -reach || x > reach || y < -reach || y > reach || z > reach) return -1;  // z >= 0
    const int side = 2 * reach + 1;
    return slot_table[static_cast<std::size_t>(((z + reach) * side + y + reach) * side + x +
                                               reach)];
  }
  std::size_t bytes() const;
};

// Integer lattice coordinates of a body's points (x, y, z per point, z = 0 in 2D) on the lattice
// through point 0 whose spacing is the shortest bond (refined over the body's extent), or an
// empty `coord` and the reason when some point is off that lattice (a point cloud).
struct LatticeCoordinates {
  double spacing = 0;
  std::vector<std::int32_t> coord;
  std::string reason;
};
LatticeCoordinates lattice_coordinates(const Body& body);

// The stencil of a body, or why it has none (then `stencil` is null): the points are not on one
// lattice, not numbered in (z, y, x) order, a family differs from the stencil's offsets, a set's
// degeneracy would depend on the vertex it is seen from, or the tables would exceed
// kStencilMemoryLimit. Built from the body's reference positions, families and constants.
struct StencilBuild {
  std::shared_ptr<const LatticeStencil> stencil;
  std::string reason;
};
StencilBuild build_lattice_stencil(const Body& body);

}  // namespace ckpd
