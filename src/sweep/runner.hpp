#pragma once
// Runs the runs of a sweep as child processes of the ckpd program (`ckpd run BASE --set ...`),
// `jobs` at a time, each with `threads` OpenMP threads. A run that crashes, goes unstable or
// rejects its case is marked failed with its message; the others go on. sweep.csv is rewritten
// (atomically) after every run, so a killed sweep keeps what finished; a rerun skips runs whose
// folder holds a completed summary under the same run key.
#include <string>

#include "src/sweep/sweep_file.hpp"
#include "src/sweep/sweep_table.hpp"

namespace ckpd::sweep {

struct RunnerOptions {
  std::string out;      // sweep output folder
  std::string program;  // the ckpd executable
  int jobs = 0;         // 0: from the hardware threads
  int threads = 0;      // per run; 0: hardware threads / jobs
  Shard shard;
  bool quiet = false;
  bool dry_run = false;
};

// Exit status of the sweep: 0 all runs completed, 4 some failed, 130 stopped by a signal.
inline constexpr int kSweepRunsFailed = 4;
int run_sweep(const Sweep& sweep, const RunnerOptions& options);

// The processors this process may use (its CPU affinity, e.g. a Slurm allocation).
int hardware_threads();

}  // namespace ckpd::sweep
