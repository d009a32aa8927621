#pragma once
// Progress of a run: on a terminal a live line redrawn in place, cut to the terminal's width
// (fields are dropped from the end, never wrapped); otherwise (a pipe, a batch log) a plain line
// every 10 s. The line shows percent, step, simulated time, elapsed time, ETA, steps/s, max
// damage and the energy balance error as of the last energy evaluation (history rows and frames
// evaluate the energy; between them only the kinetic energy is current, so an error computed
// there would mix two instants).
#include <chrono>
#include <cstdio>
#include <functional>
#include <string>

#include "src/engine/simulation.hpp"

namespace ckpd {

struct ProgressState {
  long long step = 0, total = 0;
  double time = 0;
  double elapsed = 0;  // s of wall time since the run (this process) started stepping
  double rate = 0;     // steps/s
  double max_damage = 0;
  double exact_fraction = -1;  // far field: the fraction of its points evaluated exactly; < 0: none
  long long energy_step = -1;  // step of the last energy evaluation; -1: none yet
  double energy_error = 0;     // |balance error| / max(|external work|, kinetic + strain) then
};

// The line for `state`, at most `width` characters (at least the percentage and step).
std::string format_progress(const ProgressState& state, std::size_t width);
// "12 s", "3:25", "1:02:03".
std::string format_duration(double seconds);

class ProgressReporter {
 public:
  ProgressReporter(bool enabled, long long total_steps);
  // Called after a step with an energy evaluation: the error shown from now on.
  void energy_evaluated(const Simulation& sim);
  // Called after every step; prints only when a report is due.
  void update(const Simulation& sim);
  // Ends a live line so that what follows starts on a fresh line.
  void finish();
  // Also receives every report as a plain line (the run log), every 10 s and at the end.
  void set_log(std::function<void(const std::string&)> log) { log_ = std::move(log); }

 private:
  ProgressState state(const Simulation& sim) const;

  bool enabled_;
  bool terminal_;
  long long total_;
  std::chrono::steady_clock::time_point start_, last_, last_log_;
  long long start_step_ = -1;
  long long energy_step_ = -1;
  double energy_error_ = 0;
  bool line_open_ = false;
  std::function<void(const std::string&)> log_;
};

}  // namespace ckpd
