#pragma once
// What sweep-merge trusts in a shard's folder, checked before it is merged: sweep.json names its
// sweep and a run count a sweep can have, and every row marked completed is backed by its run
// folder (a summary.json that says completed, a sweep_run.json with the row's hash).
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

namespace ckpd::sweep {

struct ShardMeta {
  nlohmann::json sweep_id, sweep_file, base;
  std::size_t runs = 0;  // 1 to kMaxRuns
};

// DIR/sweep.json; throws SweepError naming the file, the key and what was expected.
ShardMeta read_shard_meta(const std::string& dir);

// Why the run in `folder` (absolute or relative to the working folder) does not back a row
// marked completed with this hash; "" when it does.
std::string completed_run_problem(const std::string& folder, const std::string& hash);

}  // namespace ckpd::sweep
