#pragma once
// A sweep file: a base case, the parameters to vary (key paths into the case), how their values
// combine into runs, and the metrics to collect from each run's summary.json. load_sweep
// resolves every run and checks everything a run would trip over before any run starts.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "src/input/case_node.hpp"

namespace ckpd::sweep {

// Bad input in a sweep file or on the sweep command line (exit status 2, like a bad case).
class SweepError : public CaseError {
 public:
  using CaseError::CaseError;
};

// The most runs one sweep file resolves: each is a whole simulation, and resolving checks each
// run's case (about a millisecond each), so 100,000 runs resolve in a few minutes at most. A
// larger study is several sweep files. Ranges, samples and a shard's `runs` are bounded by it.
constexpr long long kMaxRuns = 100'000;

// One resolved value: its YAML text as given to `--set` ("0.01", "strain", "[0, 0, -50]") and
// its number when it is one (expressions and ranges read numbers).
struct Value {
  std::string text;
  std::optional<double> number;
};
Value make_value(const std::string& text);
Value make_value(double number);

struct Parameter {
  std::string name;
  std::string key;  // key path into the case; empty: a variable for expressions and labels
  int line = 0;     // where the sweep file declares it
  bool derived = false;
};

struct Run {
  std::size_t index = 0;
  std::string description;
  std::vector<Value> values;           // one per parameter, in declaration order
  std::vector<std::string> overrides;  // `key=value`, the sweep's fixed `set` first
  std::string hash;                    // run key: 16 hex digits
  std::string folder;                  // "0007-1a2b3c4d": index and the hash's start
};

struct Metric {
  std::string name;  // column in sweep.csv
  std::string path;  // into summary.json, e.g. contact.body_motion.sphere.velocity[2]
};

struct Sweep {
  std::string file;  // the sweep file as given
  std::string base;  // the base case, relative to the working directory
  std::string description;
  std::vector<std::string> fixed;  // `set:` overrides of every run
  std::vector<Parameter> parameters;
  std::vector<Metric> metrics;
  std::vector<Run> runs;
  std::string id;  // hash of every run's key, in order: the shards of one sweep share it
};

// Throws SweepError (file:line: key: what was expected) or CaseError for a bad base case.
Sweep load_sweep(const std::string& file);

}  // namespace ckpd::sweep
