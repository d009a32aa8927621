#pragma once
// The general path's adjacency rows, built once per body (issue 21): for every centre i, which of
// its upper neighbours (j > i, in family order: slots 0..m-1) are bonded to which, one bit row of
// W = ceil(m / 64) words per slot holding the later slots bonded to it. They depend on the
// family alone (a failed bond stays in the family; the kernel cuts its intact rows from these per
// step), so the general path copies a centre's rows instead of gathering them from the CSR rows
// at every centre and step (build_csr_rows: about a tenth of the general path's step on a 16^3
// block). The lattice stencil does the same from one table for all points; a point cloud needs
// a table per point, m W 8 bytes (488 bytes at m = 3.015 in 3D): built only up to
// kUpperRowsMemoryLimit, as the stencil is.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "bodies/bond_family.hpp"

namespace ckpd {

struct Body;

inline constexpr std::size_t kUpperRowsMemoryLimit = std::size_t{32} << 20;

struct UpperRows {
  // Point i's rows: words[start[i] ..] (m_i rows of W_i words, slot by slot); start has n + 1
  // entries.
  std::vector<std::size_t> start;
  std::vector<std::uint64_t> words;
  std::size_t bonds = 0;  // the family's stored bonds when built
  // Whether the table was built for this family (a body whose family was rebuilt has none).
  bool matches(const BondFamily& family) const {
    return start.size() == family.offset.size() && bonds == family.neighbour.size();
  }
  std::size_t bytes() const {
    return words.size() * sizeof(std::uint64_t) + start.size() * sizeof(std::size_t);
  }
};

// The bytes the table of this family would take.
std::size_t upper_rows_bytes(const BondFamily& family);
// The table, or null where it would exceed `limit` bytes.
std::shared_ptr<const UpperRows> build_upper_rows(const Body& body,
                                                  std::size_t limit = kUpperRowsMemoryLimit);

}  // namespace ckpd
