#pragma once
// sweep.csv (one row per run: index, description, hash, folder, the parameters' resolved values,
// status, message, metrics, wall time) and sweep.json (which sweep and which shard the table
// belongs to), written atomically; and sweep-merge, which joins the tables of shards.
#include <optional>
#include <string>
#include <vector>

#include "src/sweep/sweep_file.hpp"

namespace ckpd::sweep {

// What became of one run. status: pending, completed, failed, interrupted.
struct RunRecord {
  std::string status = "pending";
  std::string message;
  std::vector<std::string> metrics;  // one cell per Sweep::metrics
  std::optional<double> wall_seconds;
};

// Shard i of n (1-based); {1, 1} is the whole sweep.
struct Shard {
  int index = 1, count = 1;
  bool contains(std::size_t run) const { return static_cast<int>(run % count) == index - 1; }
  std::string text() const { return std::to_string(index) + "/" + std::to_string(count); }
};
// Parses "I/N" with 1 <= I <= N; throws SweepError otherwise.
Shard parse_shard(const std::string& text);

std::vector<std::string> table_header(const Sweep& sweep);

// Writes DIR/sweep.csv (the rows of `runs`, records[i] for runs[i]) through a temporary file and
// a rename: a reader never sees half a table.
void write_sweep_table(const std::string& dir, const Sweep& sweep,
                       const std::vector<std::size_t>& runs, const std::vector<RunRecord>& records);
void write_sweep_meta(const std::string& dir, const Sweep& sweep, const Shard& shard);

// Writes `text` to `path` through `path.tmp` and a rename.
void write_atomically(const std::string& path, const std::string& text);

// Joins the shard folders' tables into OUT/sweep.csv (rows by index, folders made relative to
// OUT). Throws SweepError when they come from different sweeps, when two hold the same run or
// when runs are missing (unless `allow_missing`). Returns the number of rows not completed.
std::size_t merge_sweep_tables(const std::vector<std::string>& dirs, const std::string& out,
                               bool allow_missing, std::string& report);

}  // namespace ckpd::sweep
