#pragma once
// Fragments: connected components of the graph of intact bonds. A specimen that split in two
// has two large components; points that lost all their bonds are components of one point.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "bodies/body.hpp"

namespace ckpd {

struct FragmentCensus {
  std::vector<std::uint32_t> label;  // component of each point, 0..count-1 in order of first point
  std::vector<std::size_t> size;     // points per component
  std::size_t count() const { return size.size(); }
  // Components with at least `min_points` points.
  std::size_t count_at_least(std::size_t min_points) const;
};

FragmentCensus find_fragments(const Body& body);

}  // namespace ckpd
