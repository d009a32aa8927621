#pragma once
// The reference lengths of a bond-only body's bonds, each bond once (from its lower-index end):
// the bond-only kernel (symmetric/bond_only.hpp) reads L and 1/L here instead of computing a
// square root and a division per bond and step. Fixed by the reference configuration.
#include <cstddef>
#include <memory>
#include <vector>

#include "bodies/bond_family.hpp"
#include "bodies/vec.hpp"

namespace ckpd {

struct UpperBonds {
  // Per point i: the CSR position of its first neighbour j > i (offset[i + 1] if none), and the
  // position of that bond in length / inverse_length (start has one more entry: the total).
  std::vector<std::size_t> first, start;
  // L = |X^j - X^i| as the symmetric kernel computes it (sqrt(x^2 + y^2 + z^2), in that order)
  // and 1 / L, per bond {i, j}, i < j, in CSR order.
  std::vector<double> length, inverse_length;
  // Whether the table was built for this family (a body whose family was rebuilt has none).
  bool matches(const BondFamily& family) const {
    return first.size() + 1 == family.offset.size() && 2 * length.size() == family.neighbour.size();
  }
};

std::shared_ptr<const UpperBonds> build_upper_bonds(const std::vector<Vec3>& reference_position,
                                                    const BondFamily& family);

}  // namespace ckpd
