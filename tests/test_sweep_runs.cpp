// `ckpd sweep` end to end on a tiny case: resolved values reach each run, a killed sweep resumes
// without redoing finished runs, shards add up to the whole sweep, an unstable run fails alone,
// bad input stops the sweep before any run.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <thread>

#include "src/sweep/csv.hpp"
#include "sweep_fixtures.hpp"

using namespace ckpd::testing;
namespace fs = std::filesystem;

namespace {

const char* kGrid = R"(base: base.yaml
parameters:
  dx: {key: bodies.block.spacing, values: [0.001, 0.002]}
  m: {key: bodies.block.horizon_ratio, range: {from: 2.5, to: 3.5, count: 3}}
metrics:
  horizon: bodies.block.horizon
  points: bodies.block.points
  steps: steps
)";

// sweep.csv as rows of column -> cell.
std::vector<std::map<std::string, std::string>> read_sweep(const fs::path& dir) {
  const auto t = ckpd::sweep::read_table((dir / "sweep.csv").string(), ',');
  std::vector<std::map<std::string, std::string>> rows;
  for (const auto& r : t.rows) {
    std::map<std::string, std::string> m;
    for (std::size_t c = 0; c < t.header.size(); ++c) m[t.header[c]] = r[c];
    rows.push_back(m);
  }
  return rows;
}

int count_status(const fs::path& dir, const std::string& status) {
  if (!fs::exists(dir / "sweep.csv")) return 0;
  int n = 0;
  for (const auto& r : read_sweep(dir)) n += r.at("status") == status;
  return n;
}

}  // namespace

TEST_CASE("a 2x3 grid runs 6 runs, each with its own resolved values", "[sweep]") {
  const auto dir = fresh_dir("sweep-grid");
  write_sweep_base(dir);
  const std::string sweep = write_file(dir / "grid.yaml", kGrid);
  const auto r = run_ckpd("sweep " + sweep + " --out " + (dir / "out").string() + " --quiet");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto rows = read_sweep(dir / "out");
  REQUIRE(rows.size() == 6);
  const double dxs[] = {0.001, 0.002}, ms[] = {2.5, 3.0, 3.5};
  for (std::size_t i = 0; i < 6; ++i) {
    const auto& row = rows[i];
    CHECK(row.at("status") == "completed");
    // The run's own summary: the spacing and horizon it was built with.
    const auto summary = read_json(dir / "out" / row.at("folder") / "summary.json");
    const auto& body = summary["bodies"][0];
    const double dx = dxs[i / 3], m = ms[i % 3];
    CHECK(body["spacing"].get<double>() == Approx(dx));
    CHECK(body["horizon"].get<double>() == Approx(m * dx));
    CHECK(body["points"].get<int>() == (i < 3 ? 400 : 100));
    CHECK(std::stod(row.at("horizon")) == Approx(m * dx));
    CHECK(row.at("steps") == "20");
    const auto record = read_json(dir / "out" / row.at("folder") / "sweep_run.json");
    CHECK(record["parameters"]["m"].get<double>() == m);
    CHECK(record["hash"] == row.at("hash"));
  }
}

TEST_CASE("a sweep killed half-way resumes without redoing finished runs", "[sweep]") {
  const auto dir = fresh_dir("sweep-resume");
  write_sweep_base(dir);
  // Longer runs (2000 steps) so that the kill lands while runs are still going.
  const std::string sweep =
      write_file(dir / "grid.yaml", std::string(kGrid) + "set: {time.steps: 2000}\n");
  const fs::path out = dir / "out";
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, STDOUT_FILENO);
    execl(CKPD_BINARY, CKPD_BINARY, "sweep", sweep.c_str(), "--out", out.c_str(), "--jobs", "1",
          "--threads-per-run", "1", "--quiet", static_cast<char*>(nullptr));
    _exit(127);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (count_status(out, "completed") < 2 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  kill(pid, SIGKILL);  // no chance to tidy up: the table must already hold what finished
  int status = 0;
  waitpid(pid, &status, 0);
  const auto before = read_sweep(out);
  std::map<std::string, fs::file_time_type> finished;
  for (const auto& row : before)
    if (row.at("status") == "completed")
      finished[row.at("folder")] = fs::last_write_time(out / row.at("folder") / "summary.json");
  REQUIRE(finished.size() >= 2);
  REQUIRE(finished.size() < 6);
  // The orphaned run got SIGTERM from the kernel (PR_SET_PDEATHSIG) and stops on its own.
  std::this_thread::sleep_for(std::chrono::milliseconds(300));

  const auto r = run_ckpd("sweep " + sweep + " --out " + out.string() + " --jobs 2");
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.output, Catch::Contains(std::to_string(finished.size()) + " done earlier, " +
                                       std::to_string(6 - finished.size()) + " to run"));
  const auto after = read_sweep(out);
  REQUIRE(after.size() == 6);
  for (const auto& row : after) CHECK(row.at("status") == "completed");
  for (const auto& [folder, time] : finished)
    CHECK(fs::last_write_time(out / folder / "summary.json") == time);
}

TEST_CASE("the shards of a sweep together equal the whole sweep", "[sweep]") {
  const auto dir = fresh_dir("sweep-shards");
  write_sweep_base(dir);
  const std::string sweep = write_file(dir / "grid.yaml", kGrid);
  const std::string common = "sweep " + sweep + " --quiet --threads-per-run 1 --out ";
  REQUIRE(run_ckpd(common + (dir / "whole").string()).exit_code == 0);
  REQUIRE(run_ckpd(common + (dir / "s1").string() + " --shard 1/2").exit_code == 0);
  REQUIRE(run_ckpd(common + (dir / "s2").string() + " --shard 2/2").exit_code == 0);
  CHECK(read_sweep(dir / "s1").size() == 3);
  CHECK(read_sweep(dir / "s2").size() == 3);
  const std::string merge = "sweep-merge " + (dir / "s1").string() + " " + (dir / "s2").string();
  const auto m = run_ckpd(merge + " --out " + (dir / "merged").string());
  INFO(m.output);
  REQUIRE(m.exit_code == 0);
  const auto whole = read_sweep(dir / "whole"), merged = read_sweep(dir / "merged");
  REQUIRE(merged.size() == whole.size());
  for (std::size_t i = 0; i < whole.size(); ++i) {
    for (const char* col :
         {"index", "description", "hash", "dx", "m", "status", "horizon", "points", "steps"})
      CHECK(merged[i].at(col) == whole[i].at(col));
    // The folder column leads from the merged table to the shard's run folder.
    CHECK(fs::exists(dir / "merged" / merged[i].at("folder") / "summary.json"));
  }
  const auto overlap = run_ckpd("sweep-merge " + (dir / "s1").string() + " " +
                                (dir / "whole").string() + " --out " + (dir / "bad").string());
  CHECK(overlap.exit_code == 2);
  CHECK_THAT(overlap.output, Catch::Contains("the shards overlap"));
  const auto missing =
      run_ckpd("sweep-merge " + (dir / "s1").string() + " --out " + (dir / "bad").string());
  CHECK(missing.exit_code == 2);
  CHECK_THAT(missing.output, Catch::Contains("3 of 6 runs missing (1, 3, 5)"));
}

TEST_CASE("an unstable run is reported failed while the others complete", "[sweep]") {
  const auto dir = fresh_dir("sweep-unstable");
  write_sweep_base(dir);
  // 2e-5 s is about 70 x the stable step of this lattice.
  const std::string sweep = write_file(dir / "dt.yaml", R"(base: base.yaml
set: {time.allow_unstable_dt: true}
parameters:
  dt: {key: time.dt, values: [auto, 2.0e-5, 1.0e-7]}
metrics: [energy.kinetic]
)");
  const auto r = run_ckpd("sweep " + sweep + " --out " + (dir / "out").string());
  INFO(r.output);
  CHECK(r.exit_code == 4);
  CHECK_THAT(r.output, Catch::Contains("(dt=2.0e-5) failed: unstable: instability at step"));
  const auto rows = read_sweep(dir / "out");
  REQUIRE(rows.size() == 3);
  CHECK(rows[0].at("status") == "completed");
  CHECK(rows[1].at("status") == "failed");
  CHECK_THAT(rows[1].at("message"), Catch::Contains("stable-step estimate"));
  CHECK(rows[2].at("status") == "completed");
  CHECK_FALSE(rows[0].at("energy.kinetic").empty());
}

TEST_CASE("bad sweep input is refused before any run starts", "[sweep]") {
  const auto dir = fresh_dir("sweep-bad");
  write_sweep_base(dir);
  auto refused = [&](const std::string& body, const std::string& args, const std::string& what) {
    const std::string sweep = write_file(dir / "bad.yaml", "base: base.yaml\n" + body);
    const fs::path out = dir / "out";
    const auto r = run_ckpd("sweep " + sweep + " --out " + out.string() + " " + args);
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.output, Catch::Contains(what));
    CHECK_FALSE(fs::exists(out));
  };
  refused(
      "parameters:\n  dx: {key: bodies.block.spacing, values: [0.001]}\n"
      "  t: {key: time.ends, values: [1]}\n",
      "", "bad.yaml:4: parameters.t.key: 'time.ends' does not exist in the base case");
  refused("parameters:\n  dx: {key: bodies.block.spacing, values: []}\n", "",
          "bad.yaml:3: parameters.dx.values: an empty list of values");
  refused("parameters:\n  dx: {key: bodies.block.spacing, range: {from: 1, to: 2, count: -1}}\n",
          "", "parameters.dx.range.count: expected a count from 1 to 100000");
  refused("parameters:\n  dx: {key: bodies.block.spacing, values: [0.001]}\n", "--shard 3/2",
          "--shard 3/2: expected I/N with 1 <= I <= N");
}

TEST_CASE("a run whose case is rejected stops the sweep before any run starts", "[sweep]") {
  const auto dir = fresh_dir("sweep-reject");
  write_sweep_base(dir);
  // A negative spacing passes the sweep's checks (the key exists) but not the case loader's:
  // each run's case is loaded before the first starts, so the sweep stops with the case's
  // message instead of failing that run (issue 18).
  const std::string sweep = write_file(dir / "dx.yaml", R"(base: base.yaml
parameters:
  dx: {key: bodies.block.spacing, values: [0.002, -0.002]}
)");
  for (const std::string args : {" --quiet", " --dry-run"}) {
    const auto r = run_ckpd("sweep " + sweep + " --out " + (dir / "out").string() + args);
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.output, Catch::Contains("dx.yaml: run 1 (dx=-0.002) does not load: --set "
                                         "bodies.block.spacing=-0.002: bodies[0].spacing"));
    CHECK_FALSE(fs::exists(dir / "out"));
  }
}

TEST_CASE("resume finds finished runs by their key when values are added to the sweep", "[sweep]") {
  const auto dir = fresh_dir("sweep-edit");
  write_sweep_base(dir);
  const fs::path out = dir / "out";
  auto sweep_with = [&](const std::string& values) {
    return write_file(dir / "s.yaml",
                      "base: base.yaml\nparameters:\n  dx: {key: "
                      "bodies.block.spacing, values: " +
                          values + "}\n");
  };
  REQUIRE(run_ckpd("sweep " + sweep_with("[0.001, 0.002]") + " --out " + out.string() + " --quiet")
              .exit_code == 0);
  const auto first = read_sweep(out);
  const auto r =
      run_ckpd("sweep " + sweep_with("[0.0025, 0.001, 0.002]") + " --out " + out.string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.output, Catch::Contains("2 done earlier, 1 to run"));
  const auto rows = read_sweep(out);
  REQUIRE(rows.size() == 3);
  // The run of 0.001 moved from index 0 to 1: same key, its folder renamed, not rerun.
  CHECK(rows[1].at("hash") == first[0].at("hash"));
  CHECK(rows[1].at("wall_seconds") != "");
  CHECK(fs::exists(out / rows[1].at("folder") / "summary.json"));
  CHECK_FALSE(fs::exists(out / first[0].at("folder")));
}

TEST_CASE(
    "a sweep stopped by SIGTERM marks its runs interrupted and continues them from "
    "their checkpoints",
    "[sweep]") {
  const auto dir = fresh_dir("sweep-term");
  write_sweep_base(dir);
  const std::string sweep = write_file(dir / "s.yaml", R"(base: base.yaml
set: {time.steps: 1500}
parameters:
  dx: {key: bodies.block.spacing, values: [0.001, 0.002]}
)");
  const fs::path out = dir / "out";
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, STDOUT_FILENO);
    dup2(null, STDERR_FILENO);
    execl(CKPD_BINARY, CKPD_BINARY, "sweep", sweep.c_str(), "--out", out.c_str(), "--jobs", "1",
          "--threads-per-run", "1", static_cast<char*>(nullptr));
    _exit(127);
  }
  // Wait until the first run has written history rows past its first.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  auto history_rows = [&] {
    int n = 0;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(out, ec))
      if (fs::exists(e.path() / "history.csv")) {
        std::ifstream in(e.path() / "history.csv");
        for (std::string line; std::getline(in, line);) ++n;
      }
    return n;
  };
  while ((!fs::exists(out) || history_rows() < 5) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  kill(pid, SIGTERM);
  int status = 0;
  waitpid(pid, &status, 0);
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 130);
  const auto rows = read_sweep(out);
  REQUIRE(rows.size() == 2);
  CHECK(rows[0].at("status") == "interrupted");
  CHECK(rows[1].at("status") == "pending");
  CHECK(fs::exists(out / rows[0].at("folder") / "checkpoint.h5"));

  const auto r = run_ckpd("sweep " + sweep + " --out " + out.string() + " --quiet");
  REQUIRE(r.exit_code == 0);
  const auto summary = read_json(out / rows[0].at("folder") / "summary.json");
  CHECK(summary["status"] == "completed");
  CHECK(summary["steps"] == 1500);
  CHECK(summary.contains("restarted_from"));
  CHECK(count_status(out, "completed") == 2);
}
