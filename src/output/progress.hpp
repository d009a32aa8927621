#pragma once
// Progress of a run: on a terminal a live line (step, simulated time, steps per second, ETA,
// max damage, energy balance error) redrawn in place; otherwise a plain line every few seconds,
// so logs of batch jobs stay short.
#include <chrono>
#include <cstdio>

#include "src/engine/simulation.hpp"

namespace ckpd {

class ProgressReporter {
 public:
  ProgressReporter(bool enabled, long long total_steps);
  // Called after every step; prints only when a report is due.
  void update(const Simulation& sim);
  // Ends a live line so that what follows starts on a fresh line.
  void finish();

 private:
  void print(const Simulation& sim);

  bool enabled_;
  bool terminal_;
  long long total_;
  std::chrono::steady_clock::time_point start_, last_;
  long long start_step_ = -1;
  bool line_open_ = false;
};

}  // namespace ckpd
