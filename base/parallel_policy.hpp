#pragma once
// When a loop is worth a parallel region: one policy for the engine (src/) and contact/, below
// both in the layering (it includes nothing of the project). Entering a parallel region costs
// microseconds, and milliseconds when another process holds a core of a shared machine, which
// is more than a small loop; the thresholds below were measured on such a machine (see where
// each is used). Tests that compare one and two threads lower them (ScopedParallelThresholds)
// so that their small scenes really run the parallel paths.
#include <cstddef>

namespace ckpd {

struct ParallelThresholds {
  // Bodies of fewer points are small: they run side by side, one thread each, and the larger
  // ones one after another with every thread (measured: 121 balls of 81 points, 9.8 ms per step
  // on one thread, 119 ms on two of a loaded machine with every small body's loops parallel).
  std::size_t engine_points = 4096;
  // The engine's streaming per-point loops over one body (the kicks, the drift, the loads, the
  // work increments: a few ns per point). Their threads wait asleep between regions (ckpd runs
  // with OMP_WAIT_POLICY=passive unless told otherwise), and waking them costs tens of us on a
  // VM: measured on the sphere-disc's 15,720-point disc at 2 threads, its far-field run (37 ms a
  // step, about 25 parallel regions) 1.4-4.9 % faster with these loops serial (PERFORMANCE.md).
  std::size_t engine_loop_points = std::size_t{1} << 15;
  // Contact narrow-phase work (points or targets; the point sums use a quarter of it) and mesh
  // wall points (measured: the per-step drift check over a 16k-point disc took 6 ms per step on
  // two threads of a loaded machine, 0.1 ms on one).
  std::size_t contact_work = 2048;
  // Streaming scans (the drift check, the boxes): a few ns per point, parallel only for very
  // many points.
  std::size_t contact_scan = std::size_t{1} << 18;
};

// The process-wide policy. Read at every loop, so a change applies from the next one.
inline ParallelThresholds& parallel_thresholds() {
  static ParallelThresholds thresholds;
  return thresholds;
}

// Sets every threshold to `work` for its lifetime (tests: 0 makes every loop parallel).
class ScopedParallelThresholds {
 public:
  explicit ScopedParallelThresholds(std::size_t work) : saved_(parallel_thresholds()) {
    parallel_thresholds() = {work, work, work, work};
  }
  ~ScopedParallelThresholds() { parallel_thresholds() = saved_; }
  ScopedParallelThresholds(const ScopedParallelThresholds&) = delete;
  ScopedParallelThresholds& operator=(const ScopedParallelThresholds&) = delete;

 private:
  ParallelThresholds saved_;
};

}  // namespace ckpd
