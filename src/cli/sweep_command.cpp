#include "src/cli/sweep_command.hpp"

#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <memory>

#include "src/cli/cli_options.hpp"
#include "src/cli/launch_guard.hpp"
#include "src/cli/setup_interrupt.hpp"
#include "src/sweep/runner.hpp"
#include "src/sweep/sweep_file.hpp"
#include "src/sweep/sweep_table.hpp"

namespace ckpd {

namespace {

struct SweepOptions {
  std::string file;
  std::string out;
  std::string shard;
  int jobs = 0;
  int threads = 0;
  bool quiet = false;
  bool dry_run = false;
};

struct MergeOptions {
  std::vector<std::string> dirs;
  std::string out;
  bool allow_missing = false;
};

// This program, to start the runs with: /proc/self/exe resolved now (the file may be replaced
// by a rebuild while the sweep runs; the resolved path then names the new one).
std::string own_program() {
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("/proc/self/exe") : exe.string();
}

int run_sweep_command(const SweepOptions& opt) {
  if (opt.shard.empty() && !opt.dry_run) {
    if (const auto refusal = parallel_launch_refusal()) {
      std::cerr << "ckpd: error: sweep: " << *refusal << '\n';
      return 2;
    }
  }
  // Resolving the sweep and loading each run's case write nothing: a signal meanwhile stops at
  // once with a message (run_sweep installs its own handlers before the first run starts).
  stop_on_signal_during_setup();
  sweep::RunnerOptions r;
  if (!opt.shard.empty()) r.shard = sweep::parse_shard(opt.shard);
  const sweep::Sweep s = sweep::load_sweep(opt.file);
  r.out = opt.out.empty() ? "runs/" + std::filesystem::path(opt.file).stem().string() : opt.out;
  r.program = own_program();
  r.jobs = opt.jobs;
  r.threads = opt.threads;
  r.quiet = opt.quiet;
  r.dry_run = opt.dry_run;
  return sweep::run_sweep(s, r);
}

int merge(const MergeOptions& opt) {
  std::string report;
  const std::size_t unfinished =
      sweep::merge_sweep_tables(opt.dirs, opt.out, opt.allow_missing, report);
  std::cout << report;
  return unfinished == 0 ? 0 : sweep::kSweepRunsFailed;
}

}  // namespace

void add_sweep_command(CLI::App& app, int& exit_status) {
  auto opt = std::make_shared<SweepOptions>();
  CLI::App* cmd =
      app.add_subcommand("sweep", "Run a parameter sweep (a sweep file over a base case)");
  cmd->add_option("sweep", opt->file, "sweep file (YAML)")->required();
  cmd->add_option("--out", opt->out, "output directory (default: runs/<sweep name>)");
  cmd->add_option("--jobs", opt->jobs,
                  "runs at a time (default: hardware threads / threads per run)")
      ->check(CLI::Range(1, kMaxThreads));
  add_threads_option(*cmd, opt->threads, "--threads-per-run",
                     "OpenMP threads of each run (default: hardware threads / jobs)");
  cmd->add_option("--shard", opt->shard,
                  "run only part I of N (1 <= I <= N; runs with index % N == I - 1), e.g. "
                  "${SLURM_ARRAY_TASK_ID}/16");
  cmd->add_flag("--dry-run", opt->dry_run, "resolve and list the runs, run nothing");
  cmd->add_flag("--quiet", opt->quiet, "print nothing but errors");
  cmd->callback([opt, &exit_status]() { exit_status = run_sweep_command(*opt); });

  auto mopt = std::make_shared<MergeOptions>();
  CLI::App* m = app.add_subcommand("sweep-merge", "Join the sweep.csv tables of a sweep's shards");
  m->add_option("dirs", mopt->dirs, "the shards' output directories")->required();
  m->add_option("--out", mopt->out, "directory for the joined sweep.csv and sweep.json")
      ->required();
  m->add_flag("--allow-missing", mopt->allow_missing,
              "join even when some runs are in no table (a warning instead of an error)");
  m->callback([mopt, &exit_status]() { exit_status = merge(*mopt); });
}

}  // namespace ckpd
