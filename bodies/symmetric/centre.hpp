#pragma once
// Point i's accumulators while the sets enumerated from it are processed: its own force and
// energy (kept in registers, flushed once) and the evaluation's counters.
#include "bodies/symmetric/context.hpp"

namespace ckpd::symmetric {

struct Centre {
  std::uint32_t index = 0;
  double fx = 0, fy = 0, fz = 0, w = 0;
  SymmetricKernelStats count;

  // Adds a per-vertex term to vertex 0 (i, `slot` ignored) or to a slot of thread t.
  template <bool kEnergy>
  void add(SymmetricKernelThread& t, std::size_t slot, bool is_i, const Vec3& f, double e) {
    if (is_i) {
      fx += f.x();
      fy += f.y();
      fz += f.z();
      if constexpr (kEnergy) w += e;
    } else {
      t.fx[slot] += f.x();
      t.fy[slot] += f.y();
      t.fz[slot] += f.z();
      if constexpr (kEnergy) t.w[slot] += e;
    }
  }
};

}  // namespace ckpd::symmetric
