#pragma once
// Row classes of the far field's linear operator (issue 20: "one block row per family shape
// class" on lattice bodies). Row i of the operator (linear_operator.hpp) is built from the sets
// of the centres c in {i} and i's family that hold i, whose vertices are all bonded to i (a
// set's edges are bonds), so everything it reads lies in {i} and i's family: the members'
// positions relative to i, their volumes and effective volumes dV1, dV2, dV3 (the centres'
// weights and the receiving point's volume), the intact flags of their bonds, and body-wide
// constants. Two points of a lattice body whose members, in family order, sit at the same
// integer offsets with the same (bitwise) volumes and effective volumes, and whose members'
// bonds are all intact, have the same row up to the rounding of their positions: one class.
// The key is therefore exact, not a tolerance: a point is put in a class only after its key has
// been compared in full with the class's first point. Points with a failed bond among their
// members (a pre-crack at set-up) and points of bodies off a lattice are classes of their own.
//
// Classes related by a symmetry of the cubic lattice share the assembly as well. Let S be a
// signed permutation of the axes (48 in 3D, the 8 that keep z in 2D): if class p's members sit
// at the offsets S o of class r's members o, with the same volumes and effective volumes, then
// p's neighbourhood is r's mirrored or turned, and since the force law is isotropic the
// displacement field u'(x) = S u(S^T x) gives the forces b'(x) = S b(S^T x); to first order
// sum_o K^p(S o) u'(p + S o) = S sum_o K^r(o) u(r + o), that is
//   K^p(S o) = S K^r(o) S^T,
// block by block. So only one class of each such orbit is assembled (the one with the smallest
// first point) and the others' rows are its blocks turned (linear_operator.cpp). On the
// sphere-disc's disc (issue 20) the rim's classes fall into orbits of up to 16 (the square's 8
// symmetries times the flip of the two layers), and the assembly visits only the centres near
// one sixteenth of the rim.
#include <array>
#include <cstdint>
#include <vector>

namespace ckpd {

struct Body;

// A signed permutation of the axes: (S o)_d = sign[d] o_perm[d], the matrix S(d, perm[d]) =
// sign[d].
struct LatticeSymmetry {
  std::array<int, 3> perm{0, 1, 2};
  std::array<int, 3> sign{1, 1, 1};
};
// The 48 signed permutations, the identity first; in 2D only the first 8 are used (those that
// keep z: perm[2] == 2, sign[2] == 1).
const std::array<LatticeSymmetry, 48>& lattice_symmetries();
inline std::size_t lattice_symmetry_count(int dimension) {
  return dimension == 2 ? 8 : 48;
}

// A row's members by lattice offset, in a cube of side 2 reach + 1 around the row's point: the
// member's slot at each offset, -1 where none (the orbit search and the turned rows look members
// up by offset). Filled for one row at a time and cleared after it.
class OffsetTable {
 public:
  using Offset = std::array<std::int64_t, 3>;
  explicit OffsetTable(std::int64_t reach)
      : reach_(reach),
        side_(2 * reach + 1),
        slot_(static_cast<std::size_t>(side_ * side_ * side_), -1) {}
  void set(const Offset& o, std::int32_t slot) { slot_[cell(o)] = slot; }
  // The slot at offset o, -1 where none (or o outside the cube).
  std::int32_t at(const Offset& o) const {
    for (std::int64_t x : o)
      if (x < -reach_ || x > reach_) return -1;
    return slot_[cell(o)];
  }

 private:
  std::size_t cell(const Offset& o) const {
    return static_cast<std::size_t>(((o[2] + reach_) * side_ + o[1] + reach_) * side_ + o[0] +
                                    reach_);
  }
  std::int64_t reach_, side_;
  std::vector<std::int32_t> slot_;
};

struct RowClasses {
  // Per point, the first point of its class (itself for a class's first point): a class's
  // first point has the smallest index of the class.
  std::vector<std::uint32_t> first;
  // Per class's first point p: the first point of the class whose row p's row is turned from
  // (p itself where p's row is assembled), and the symmetry S (index into lattice_symmetries())
  // with p's members at S times the source's members' offsets. Unused for other points.
  std::vector<std::uint32_t> source;
  std::vector<std::uint8_t> symmetry;
  // Per point, its lattice coordinates (3 per point; empty off a lattice), and the largest
  // member offset component of the classes (an OffsetTable's reach; 0 without turned rows).
  std::vector<std::int32_t> coord;
  std::int64_t reach = 0;
};

RowClasses operator_row_classes(const Body& body);

}  // namespace ckpd
