#include "bodies/upper_bonds.hpp"

#include <algorithm>
#include <cmath>

namespace ckpd {

std::shared_ptr<const UpperBonds> build_upper_bonds(const std::vector<Vec3>& reference_position,
                                                    const BondFamily& family) {
  auto table = std::make_shared<UpperBonds>();
  const std::size_t n = family.points();
  table->first.resize(n);
  table->start.resize(n + 1);
  const std::uint32_t* nb = family.neighbour.data();
  std::size_t bonds = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t begin = family.offset[i], end = family.offset[i + 1];
    table->first[i] = static_cast<std::size_t>(
        std::upper_bound(nb + begin, nb + end, static_cast<std::uint32_t>(i)) - nb);
    table->start[i] = bonds;
    bonds += end - table->first[i];
  }
  table->start[n] = bonds;
  table->length.resize(bonds);
  table->inverse_length.resize(bonds);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 Xi = reference_position[i];
    std::size_t b = table->start[i];
    for (std::size_t k = table->first[i]; k < family.offset[i + 1]; ++k, ++b) {
      const Vec3 R = reference_position[nb[k]] - Xi;
      const double x = R.x(), y = R.y(), z = R.z();
      const double L = std::sqrt(x * x + y * y + z * z);
      table->length[b] = L;
      table->inverse_length[b] = 1 / L;
    }
  }
  return table;
}

}  // namespace ckpd
