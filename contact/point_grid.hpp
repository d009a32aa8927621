#pragma once
// A cell list over some points of one body at their current positions, with cells at least as
// wide as the search radius: every point within that radius of a query lies in the 3 x 3 (x 3)
// cells around it. Positions and volumes are copied in cell order, so a query reads memory in
// sequence. Built serially: a point's partners come in the same order on every thread count.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "contact/point_set.hpp"

namespace ckpd {

class PointGrid {
 public:
  // Bins the points `members` of `points`; `radius` is the largest query radius.
  void build(const PointSet& points, const std::vector<std::uint32_t>& members, double radius);
  // Room for builds of up to `points` members (and the cells build allows them, 2 points + 64):
  // a build within it allocates nothing.
  void reserve(std::size_t points);

  std::size_t size() const { return point_.size(); }

  // Calls f(point, position, volume) for every binned point within the cells around x (a
  // superset of those within the radius), in a fixed order.
  template <class F>
  void for_each_near(const Vec3& x, F&& f) const {
    if (point_.empty()) return;
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      const double c = std::floor((x[a] - origin_[a]) * inverse_cell_);
      if (c < -1 || c > dims_[a]) return;  // more than a cell outside: nothing within reach
      const int ci = static_cast<int>(c);
      lo[a] = std::max(ci - 1, 0);
      hi[a] = std::min(ci + 1, dims_[a] - 1);
    }
    for (int cz = lo[2]; cz <= hi[2]; ++cz)
      for (int cy = lo[1]; cy <= hi[1]; ++cy) {
        const std::size_t row = (static_cast<std::size_t>(cz) * dims_[1] + cy) * dims_[0];
        const std::uint32_t begin = cell_start_[row + lo[0]], end = cell_start_[row + hi[0] + 1];
        for (std::uint32_t k = begin; k < end; ++k) f(point_[k], position_[k], volume_[k]);
      }
  }

 private:
  Vec3 origin_ = Vec3::Zero();
  double inverse_cell_ = 0;
  int dims_[3] = {0, 0, 0};
  std::vector<std::uint32_t> cell_start_;  // per cell (x fastest), plus one
  std::vector<std::uint32_t> point_;       // body point indices in cell order
  std::vector<Vec3> position_;
  std::vector<double> volume_;
  std::vector<std::uint32_t> cell_of_;    // scratch: cell of each member
  std::vector<std::uint32_t> next_slot_;  // scratch: next free slot per cell
};

}  // namespace ckpd
