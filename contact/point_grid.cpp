#include "contact/point_grid.hpp"

#include <limits>

namespace ckpd {

void PointGrid::reserve(std::size_t points) {
  point_.reserve(points);
  position_.reserve(points);
  volume_.reserve(points);
  cell_of_.reserve(points);
  // build's cap on the cells: 2 n + 64, and cell_start_ holds one more.
  cell_start_.reserve(2 * points + 65);
  next_slot_.reserve(2 * points + 65);
}

void PointGrid::build(const PointSet& body, const std::vector<std::uint32_t>& members,
                      double radius) {
  const std::size_t n = members.size();
  point_.resize(n);
  position_.resize(n);
  volume_.resize(n);
  if (n == 0) return;
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (std::uint32_t i : members) {
    const Vec3 x = body.position(i);
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  // Cells no narrower than the radius; widened when a sparse set would make too many of them.
  double cell = radius;
  const double cap = 2.0 * static_cast<double>(n) + 64;
  for (;;) {
    double cells = 1;
    for (int a = 0; a < 3; ++a) cells *= std::floor((hi[a] - lo[a]) / cell) + 1;
    if (cells <= cap) break;
    cell *= std::max(1.01, std::cbrt(cells / cap));
  }
  origin_ = lo;
  inverse_cell_ = 1 / cell;
  for (int a = 0; a < 3; ++a)
    dims_[a] = static_cast<int>(std::floor((hi[a] - lo[a]) * inverse_cell_)) + 1;
  const std::size_t cells = static_cast<std::size_t>(dims_[0]) * dims_[1] * dims_[2];
  cell_start_.assign(cells + 1, 0);
  cell_of_.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3 x = body.position(members[k]);
    std::size_t c = 0;
    for (int a = 2; a >= 0; --a) {
      const int ca = std::min(static_cast<int>((x[a] - lo[a]) * inverse_cell_), dims_[a] - 1);
      c = c * dims_[a] + ca;
    }
    cell_of_[k] = static_cast<std::uint32_t>(c);
    ++cell_start_[c + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) cell_start_[c + 1] += cell_start_[c];
  next_slot_.assign(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t slot = next_slot_[cell_of_[k]]++;
    const std::uint32_t i = members[k];
    point_[slot] = i;
    position_[slot] = body.position(i);
    volume_[slot] = body.volume[i];
  }
}

}  // namespace ckpd
