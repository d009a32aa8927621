#pragma once
// A run with the output of `ckpd run`: the history row and field frame at the start, then after
// each step the history rows, field frames and checkpoints that are due, and summary.json when
// the run stops. `ckpd run` and the Python module both step through it, so the same case writes
// the same files from either. Without an output folder it writes nothing but keeps the same
// schedule of energy evaluations (so the energy guard runs on the same steps).
#include <chrono>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "src/output/field_writer.hpp"
#include "src/output/progress.hpp"
#include "src/output/run_log.hpp"
#include "src/output/run_output.hpp"

namespace ckpd {

struct RunDriverOptions {
  // Output folder (created by rank 0); empty: no files at all. The same on every rank of an MPI
  // run: rank 0 writes the files, except that the ranks of a distributed run write frames and
  // checkpoints together where HDF5 is parallel (output_share.hpp).
  std::string out;
  std::string restarted_from;  // the checkpoint the simulation was restored from, if any
  bool progress = false;       // the progress line on stdout
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  double setup_seconds = 0;  // case loading and set-up, for the summary
  // DIR/run.log's first lines (version, command line, overrides, set-up), and what summary.json
  // records of how the run was made; both empty: nothing of the kind.
  std::vector<std::string> log_header;
  nlohmann::ordered_json provenance;
  // An MPI run: summary.json's `decomposition` (the ranks' shares and what they exchange).
  nlohmann::ordered_json decomposition;
};

class RunDriver {
 public:
  // Creates the folder, checks that every file the run writes can go where it goes
  // (output_paths.hpp), starts (or, after a restart, continues) history.csv and the field
  // frames, removes an earlier summary.json and writes the initial row and frame. Throws
  // std::runtime_error naming a path that cannot be written; a new run then leaves no file in
  // the folder. A write that fails later (a full disk) throws OutputError from step(),
  // write_checkpoint() or stop(): the file it was writing keeps its previous version, and the
  // run must end with a failure (no summary is written for it).
  RunDriver(Simulation& sim, RunDriverOptions options);

  // The run's steps: fixed, or with an adaptive step the current estimate
  // (Simulation::planned_steps).
  long long total_steps() const { return sim_.adaptive() ? sim_.planned_steps() : total_; }
  bool finished() const { return sim_.step() >= total_steps(); }
  // One step and the output due after it. `with_energy` also evaluates the strain energy when
  // no output needs it (a caller that reads the energies after this step). Throws
  // InstabilityError (or TunnellingError) from the step; call stop() then.
  void step(bool with_energy = false);
  // Writes DIR/checkpoint.h5 unless this step has written it already.
  void write_checkpoint();
  // Ends the run: the history row of the current step (unless it has one) and summary.json
  // with `status` ("completed", "unstable", ...) and `message`; the log's last line.
  void stop(const std::string& status, const std::string& message);
  // A line for DIR/run.log (none without an output folder).
  void log(const std::string& line);
  // The summary as it would be written now.
  nlohmann::ordered_json summary(const std::string& status, const std::string& message) const;

  const std::string& out() const { return options_.out; }
  std::string checkpoint_path() const { return options_.out + "/checkpoint.h5"; }
  double seconds() const;

 private:
  bool frame_due(long long step, double time) const;
  // Rank 0's whole scene made current for the output (a distributed run's gather, a collective),
  // once per step: a checkpoint after a row or frame of the same step does not gather again.
  void gather();
  void report_inversion();
  void abandon_output();  // a failed start: what the set-up wrote removed
  void write_frame();
  void write_row();  // the history row of this step (every rank takes part)

  Simulation& sim_;
  RunDriverOptions options_;
  long long resume_ = -1;
  long long total_ = 0;
  long long interval_ = 1;
  std::optional<HistoryWriter> history_;
  std::optional<FieldWriter> fields_;
  std::optional<RunLog> log_;
  ProgressReporter progress_;
  long long row_step_ = -1;         // the step of the last history row
  long long checkpoint_step_ = -1;  // the step of the last checkpoint
  long long gathered_step_ = -1;    // the step whose state the whole scene holds
  bool inversion_reported_ = false;
  bool writes_;       // this process writes the files (rank 0 of a run with an output folder)
  bool shared_;       // frames and checkpoints written by all ranks together (output_share.hpp)
  bool row_gathers_;  // a history row reads the whole scene (a chosen quantity labels fragments)
  bool has_history_ = false;  // rank 0 writes a history (known on every rank)
};

}  // namespace ckpd
