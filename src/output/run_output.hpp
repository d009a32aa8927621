#pragma once
// What a run writes: DIR/history.csv, one row per history interval, written as it comes so an
// interrupted run keeps its rows (a row is whole in the file or not there: durable_file.hpp's
// AppendFile); DIR/summary.json at the end, with the run's status, replacing the file only
// when complete.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "src/engine/simulation.hpp"
#include "src/output/durable_file.hpp"

namespace ckpd {

class HistoryWriter {
 public:
  // Throws std::runtime_error (OutputError) naming the path when it cannot be written. With
  // `resume_after_step` >= 0 (a restart) an existing history keeps its rows up to that step that
  // lie on the schedule of rows (steps that are multiples of `interval`: the row a run stopped
  // by a signal writes at its last step is not one the run it continues would write) and is
  // continued; otherwise it starts anew. Either way the file is replaced whole.
  // `chosen`: the case's extra columns (output.history), after the default ones.
  explicit HistoryWriter(const std::string& path, long long resume_after_step = -1,
                         std::vector<HistoryQuantity> chosen = {}, bool far_field = false,
                         long long interval = 1);
  // One row per step: a second call at the step of the last row (kept from before a restart
  // or written by this process) writes nothing. `chosen`: the chosen quantities' values
  // (history_values), computed by every rank of a distributed run.
  void write_row(const Simulation& sim, const std::vector<double>& chosen);
  // The rows written so far synced to the disk (with each checkpoint).
  void sync() { out_.sync(); }

 private:
  AppendFile out_;
  std::vector<HistoryQuantity> chosen_;
  long long last_step_ = -1;  // the step of the last row in the file
  bool far_field_ = false;    // a last column exact_fraction (some body has a far field)
};

// Peak resident set size of this process in MB.
double peak_rss_mb();

// The first sighting of inverted tetrahedra/triangles as a warning naming step, time and body
// ("" when none was seen), and the summary's "inversion" object (final, max, first, warning).
std::string inversion_warning(const Simulation& sim);
nlohmann::ordered_json inversion_summary(const Simulation& sim);

// The summary object: status ("completed", "unstable", ...), counts, time step, energies.
nlohmann::ordered_json make_summary(const Simulation& sim, const std::string& status,
                                    const std::string& message, double wall_seconds);
// Replaces `path` with `json` once it is written whole (durable_file.hpp).
void write_json(const std::string& path, const nlohmann::ordered_json& json);

}  // namespace ckpd
