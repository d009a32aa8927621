#pragma once
// One-neighbour families H1 (THEORY.md section 1) in compressed sparse rows: the neighbours of
// point i are neighbour[offset[i] .. offset[i+1]), sorted by index. Built once, in the
// reference configuration, with a cell list; every bond is stored from both ends, so a point's
// sum is its own and needs no locking.
#include <cstdint>
#include <vector>

#include "bodies/vec.hpp"

namespace ckpd {

// Relative tolerance on the horizon: |X^j - X^i| <= delta (1 + 1e-12) is a bond. Lattice
// offsets that equal delta up to round-off are inside on every machine.
inline constexpr double kHorizonTolerance = 1e-12;

inline bool within_horizon(const Vec3& offset, double horizon) {
  const double limit = horizon * (1 + kHorizonTolerance);
  return offset.squaredNorm() <= limit * limit;
}

struct BondFamily {
  std::vector<std::size_t> offset;       // size points + 1
  std::vector<std::uint32_t> neighbour;  // size bonds (each bond twice: i->j and j->i)

  std::size_t points() const { return offset.empty() ? 0 : offset.size() - 1; }
  std::size_t bond_entries() const { return neighbour.size(); }
  std::size_t family_size(std::size_t i) const { return offset[i + 1] - offset[i]; }
};

// Builds H1 for all points; throws std::invalid_argument on non-finite positions or when the
// point count does not fit 32-bit indices.
BondFamily build_bond_family(const std::vector<Vec3>& reference_position, double horizon);

}  // namespace ckpd
