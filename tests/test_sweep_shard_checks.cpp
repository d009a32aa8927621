// sweep-merge trusts nothing in a shard's folder unchecked (src/sweep/shard_check.hpp): a
// sweep.json whose `runs` no sweep can have, or that lacks a key, is refused naming the file and
// the key (it allocated until bad_alloc, or exited 1 with the JSON library's words); a row
// marked completed whose run folder is gone or whose summary says otherwise is refused, or left
// out with --allow-missing. Sweep files get the case files' checks of the YAML itself.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>

#include "run_helpers.hpp"
#include "src/sweep/sweep_file.hpp"
#include "sweep_fixtures.hpp"

namespace fs = std::filesystem;
using namespace ckpd::testing;

namespace {

const char* kPair = R"(base: base.yaml
parameters:
  dx: {key: bodies.block.spacing, values: [0.001, 0.002]}
)";

// A sweep of two runs in DIR/s1 (shard 1/2) and DIR/s2 (shard 2/2).
void run_two_shards(const fs::path& dir) {
  write_sweep_base(dir);
  const std::string sweep = write_file(dir / "pair.yaml", kPair);
  for (const char* shard : {"1/2", "2/2"}) {
    const fs::path out = dir / (std::string("s") + shard[0]);
    const CommandResult r = run_ckpd("sweep " + sweep + " --quiet --threads-per-run 1 --shard " +
                                     shard + " --out " + out.string());
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
  }
}

CommandResult merge(const fs::path& dir, const std::string& extra = "") {
  return run_ckpd("sweep-merge " + (dir / "s1").string() + " " + (dir / "s2").string() + " --out " +
                  (dir / "merged").string() + extra);
}

void edit_meta(const fs::path& dir, const std::function<void(nlohmann::json&)>& edit) {
  nlohmann::json j = read_json(dir / "sweep.json");
  edit(j);
  std::ofstream(dir / "sweep.json") << j.dump(2);
}

// The folder of the run in shard DIR's table (one run per shard here).
fs::path run_folder(const fs::path& dir) {
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.is_directory()) return entry.path();
  FAIL("no run folder in " << dir);
  return {};
}

std::string sweep_error(const std::string& file) {
  try {
    ckpd::sweep::load_sweep(file);
  } catch (const ckpd::CaseError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("a shard's sweep.json with a run count no sweep has is refused", "[sweep]") {
  const auto dir = fresh_dir("shard-runs");
  run_two_shards(dir);
  REQUIRE(merge(dir).exit_code == 0);
  for (const std::string runs : {"1e15", "-1", "1e300", "1000000000000000", "0", "\"2\""}) {
    edit_meta(dir / "s2", [&](nlohmann::json& j) { j["runs"] = nlohmann::json::parse(runs); });
    fs::remove_all(dir / "merged");
    const CommandResult r = merge(dir);
    INFO(runs << ": " << r.output);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.output, Catch::Contains("s2/sweep.json: runs: expected a whole number of runs "
                                         "from 1 to 100000"));
    CHECK_FALSE(fs::exists(dir / "merged"));
  }
  // In the first shard too (its count is the one the merge goes by).
  edit_meta(dir / "s1", [](nlohmann::json& j) { j["runs"] = 1e15; });
  CHECK(merge(dir).exit_code == 2);
}

TEST_CASE("a shard's sweep.json without sweep_id or runs is refused naming the key", "[sweep]") {
  const auto dir = fresh_dir("shard-keys");
  run_two_shards(dir);
  for (const char* key : {"sweep_id", "runs"}) {
    const nlohmann::json before = read_json(dir / "s1" / "sweep.json");
    edit_meta(dir / "s1", [&](nlohmann::json& j) { j.erase(key); });
    const CommandResult r = merge(dir);
    INFO(key << ": " << r.output);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.output, Catch::Contains("s1/sweep.json: missing key '" + std::string(key) + "'"));
    std::ofstream(dir / "s1" / "sweep.json") << before.dump(2);
  }
  std::ofstream(dir / "s1" / "sweep.json") << "[1, 2]";
  const CommandResult r = merge(dir);
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.output, Catch::Contains("s1/sweep.json: expected an object"));
}

TEST_CASE("a completed row whose run folder does not back it is not merged as completed",
          "[sweep]") {
  const auto dir = fresh_dir("shard-rows");
  run_two_shards(dir);
  const fs::path folder = run_folder(dir / "s2");
  SECTION("the summary says unstable") {
    nlohmann::json summary = read_json(folder / "summary.json");
    summary["status"] = "unstable";
    std::ofstream(folder / "summary.json") << summary.dump(2);
    const CommandResult r = merge(dir);
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.output, Catch::Contains("is marked completed but") &&
                             Catch::Contains("summary.json says status \"unstable\""));
    CHECK_FALSE(fs::exists(dir / "merged" / "sweep.csv"));
  }
  SECTION("the run folder is gone") {
    fs::remove_all(folder);
    const CommandResult r = merge(dir);
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.output,
               Catch::Contains("is marked completed but its folder") && Catch::Contains("is gone"));
    // --allow-missing leaves the row out, says so, and counts it as not completed.
    const CommandResult m = merge(dir, " --allow-missing");
    INFO(m.output);
    CHECK(m.exit_code != 0);
    CHECK_THAT(m.output, Catch::Contains("left out"));
    std::ifstream table(dir / "merged" / "sweep.csv");
    std::string line;
    int rows = 0;
    while (std::getline(table, line)) ++rows;
    CHECK(rows == 2);  // the header and the one backed run
  }
}

TEST_CASE("a sweep file gets the case files' checks of its YAML", "[sweep]") {
  const auto dir = fresh_dir("sweep-yaml");
  write_sweep_base(dir);
  // A complex key: yaml-cpp's "bad conversion", exit 1.
  CHECK_THAT(
      sweep_error(write_file(dir / "complex.yaml",
                             "base: base.yaml\nparameters:\n  ? [a, b]\n  : {values: [1]}\n")),
      Catch::Contains("complex.yaml:3: parameters: a key must be a plain name"));
  // Nesting past the depth guard: "YAML syntax error: bad file".
  std::string deep = "base: base.yaml\nparameters:\n  v: {key: time.steps, values: ";
  deep += std::string(600, '[') + "1" + std::string(600, ']') + "}\n";
  CHECK_THAT(sweep_error(write_file(dir / "deep.yaml", deep)),
             Catch::Contains("deep.yaml:3: nested deeper than"));
  CHECK_THAT(sweep_error(write_file(dir / "cycle.yaml", "base: base.yaml\nx: &x [*x]\n")),
             Catch::Contains("cycle.yaml:2: an alias inside the node"));
  const CommandResult r = run_ckpd("sweep " + (dir / "complex.yaml").string() + " --dry-run");
  INFO(r.output);
  CHECK(r.exit_code == 2);
}
