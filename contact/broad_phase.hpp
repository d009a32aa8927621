#pragma once
// Broad phase: which bodies' bounding boxes overlap. One FCL dynamic AABB tree over one box per
// body; FCL stays behind this interface (its headers are heavy and templated).
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "bodies/vec.hpp"

namespace ckpd {

struct Box3 {
  Vec3 lo, hi;
};

class BroadPhase {
 public:
  // `members`: the indices of the bodies that take part (the others are never reported).
  explicit BroadPhase(const std::vector<std::size_t>& members);
  ~BroadPhase();
  BroadPhase(const BroadPhase&) = delete;
  BroadPhase& operator=(const BroadPhase&) = delete;

  // `boxes[b]` is body b's box (indexed by body; only members are read). Returns the member pairs
  // (a < b) whose boxes overlap (touching counts), sorted.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> overlapping_pairs(
      const std::vector<Box3>& boxes);
  // The same into `pairs` (cleared first; its buffer is reused: no allocation in a time step
  // once it has held the most pairs).
  void overlapping_pairs(const std::vector<Box3>& boxes,
                         std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs);

 private:
  struct Tree;
  std::unique_ptr<Tree> tree_;
};

}  // namespace ckpd
