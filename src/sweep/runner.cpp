#include "src/sweep/runner.hpp"

#include <fcntl.h>
#include <sched.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <thread>

#include "src/case/case_loader.hpp"
#include "src/sweep/generators.hpp"
#include "src/sweep/json_path.hpp"

namespace ckpd::sweep {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

volatile std::sig_atomic_t stop_signal = 0;
extern "C" void on_stop_signal(int sig) {
  stop_signal = sig;
}

std::optional<nlohmann::json> read_json(const fs::path& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    return std::nullopt;
  }
}

// The run's own record: what it was asked to compute. Resume compares `hash`.
void write_run_record(const fs::path& folder, const Sweep& sweep, const Run& run) {
  nlohmann::ordered_json j;
  j["index"] = run.index;
  j["description"] = run.description;
  j["hash"] = run.hash;
  j["sweep_id"] = sweep.id;
  j["base"] = sweep.base;
  nlohmann::ordered_json params;
  for (std::size_t i = 0; i < run.values.size(); ++i) {
    const Value& v = run.values[i];
    params[sweep.parameters[i].name] =
        v.number ? nlohmann::ordered_json(*v.number) : nlohmann::ordered_json(v.text);
  }
  j["parameters"] = params;
  j["overrides"] = run.overrides;
  write_atomically((folder / "sweep_run.json").string(), j.dump(2) + "\n");
  YAML::Emitter case_text;
  case_text << load_case_yaml(sweep.base, run.overrides);
  write_atomically((folder / "case.yaml").string(),
                   "# resolved case of sweep run " + std::to_string(run.index) + " (" +
                       run.description + "), for reference; the run read " + sweep.base +
                       " with the overrides in sweep_run.json\n" + case_text.c_str() + "\n");
}

// A folder of a finished run with this key: `folder` itself, or one of an earlier version of
// the sweep (other index, same key), which is renamed to `folder`.
bool finished_earlier(const fs::path& out, const Run& run) {
  auto complete = [&](const fs::path& dir) {
    const auto summary = read_json(dir / "summary.json");
    const auto record = read_json(dir / "sweep_run.json");
    return summary && record && summary->value("status", "") == "completed" &&
           record->value("hash", "") == run.hash;
  };
  const fs::path own = out / run.folder;
  if (fs::exists(own)) return complete(own);
  std::error_code ec;
  const std::string suffix = run.folder.substr(run.folder.find('-'));
  for (const auto& entry : fs::directory_iterator(out, ec)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_directory() && name.size() > suffix.size() &&
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0 &&
        complete(entry.path())) {
      fs::rename(entry.path(), own);
      return true;
    }
  }
  return false;
}

// The folder holds an interrupted run of this key with its checkpoint.
bool can_continue(const fs::path& folder, const Run& run) {
  const auto summary = read_json(folder / "summary.json");
  const auto record = read_json(folder / "sweep_run.json");
  return summary && record && summary->value("status", "") == "interrupted" &&
         record->value("hash", "") == run.hash && fs::is_regular_file(folder / "checkpoint.h5");
}

void collect_metrics(const Sweep& sweep, const nlohmann::json& summary, RunRecord& rec,
                     std::map<std::string, bool>& warned, bool quiet) {
  rec.metrics.assign(sweep.metrics.size(), "");
  for (std::size_t m = 0; m < sweep.metrics.size(); ++m) {
    std::string missing;
    const auto v = find_json(summary, sweep.metrics[m].path, missing);
    if (v) {
      rec.metrics[m] = json_cell(*v);
    } else if (!warned[sweep.metrics[m].name] && !quiet) {
      warned[sweep.metrics[m].name] = true;
      std::cerr << "ckpd sweep: warning: metric '" << sweep.metrics[m].name
                << "': summary.json has no '" << missing << "' (cell left empty)\n";
    }
  }
}

// The last non-empty lines of the run's stderr, without the "ckpd: error: " prefix.
std::string error_message(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);)
    if (line.find_first_not_of(" \t\r") != std::string::npos) lines.push_back(line);
  std::string msg;
  for (std::size_t i = lines.size() > 3 ? lines.size() - 3 : 0; i < lines.size(); ++i) {
    std::string l = lines[i];
    for (const std::string prefix : {"ckpd: error: ", "ckpd: "})
      if (l.rfind(prefix, 0) == 0) l = l.substr(prefix.size());
    msg += (msg.empty() ? "" : " | ") + l;
  }
  if (msg.size() > 500) msg = msg.substr(0, 500) + "...";
  return msg;
}

std::string clock_text(double seconds) {
  const long s = std::lround(seconds);
  char buf[32];
  if (s >= 3600)
    std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  else
    std::snprintf(buf, sizeof buf, "%ld:%02ld", s / 60, s % 60);
  return buf;
}

// Every run still to do must load as `ckpd run` would load it (keys, values and their bounds,
// bodies, conditions, contact, output), without running: a `set:` key the case does not know
// or a value out of bounds then stops the sweep (and --dry-run) with the run and the key named,
// instead of failing every run.
void check_runs_load(const Sweep& sweep, const std::vector<std::size_t>& mine,
                     const std::vector<std::size_t>& todo) {
  for (std::size_t k : todo) {
    const Run& run = sweep.runs[mine[k]];
    try {
      load_scene(sweep.base, run.overrides);
    } catch (const CaseError& e) {
      throw SweepError(sweep.file + ": run " + std::to_string(run.index) + " (" + run.description +
                       ") does not load: " + e.what());
    }
  }
}

struct Child {
  std::size_t slot;  // position in the shard's list
  Clock::time_point start;
};

}  // namespace

int hardware_threads() {
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof set, &set) == 0) return std::max(1, CPU_COUNT(&set));
  return std::max(1u, std::thread::hardware_concurrency());
}

int run_sweep(const Sweep& sweep, const RunnerOptions& opt) {
  const fs::path out = opt.out;
  std::vector<std::size_t> mine;
  for (const Run& run : sweep.runs)
    if (opt.shard.contains(run.index)) mine.push_back(run.index);
  std::vector<RunRecord> records(mine.size());
  std::vector<std::size_t> todo;
  std::map<std::string, bool> warned;
  for (std::size_t k = 0; k < mine.size(); ++k) {
    const Run& run = sweep.runs[mine[k]];
    if (fs::is_directory(out) && finished_earlier(out, run)) {
      records[k].status = "completed";
      const auto summary = read_json(out / run.folder / "summary.json");
      collect_metrics(sweep, *summary, records[k], warned, opt.quiet);
      if (summary->contains("wall_seconds")) records[k].wall_seconds = (*summary)["wall_seconds"];
    } else {
      todo.push_back(k);
    }
  }

  if (!todo.empty() && !opt.quiet)
    std::cout << "sweep: checking that the " << todo.size() << " runs to do load" << std::endl;
  check_runs_load(sweep, mine, todo);
  if (!opt.dry_run) fs::create_directories(out);

  const int hw = hardware_threads();
  int jobs = opt.jobs, threads = opt.threads;
  const int want = std::max<int>(1, static_cast<int>(todo.size()));
  if (jobs <= 0 && threads <= 0) jobs = std::min(hw, want);
  if (jobs <= 0) jobs = std::min(want, std::max(1, hw / threads));
  if (threads <= 0) threads = std::max(1, hw / jobs);
  if (!opt.quiet || opt.dry_run) {
    std::cout << "sweep " << sweep.file << ": " << sweep.runs.size() << " runs of " << sweep.base;
    if (opt.shard.count > 1) std::cout << ", shard " << opt.shard.text() << ": " << mine.size();
    std::cout << "; " << mine.size() - todo.size() << " done earlier, " << todo.size()
              << " to run, " << jobs << " at a time x " << threads << " threads (" << hw
              << " hardware threads); results in " << out.string() << "\n";
    if (jobs * threads > hw)
      std::cout << "warning: " << jobs << " jobs x " << threads << " threads exceed the " << hw
                << " hardware threads\n";
  }
  if (opt.dry_run) {
    for (std::size_t k = 0; k < mine.size(); ++k) {
      const Run& run = sweep.runs[mine[k]];
      std::cout << run.folder << "  " << (records[k].status == "completed" ? "done " : "to run")
                << "  " << run.description << "\n";
      for (const std::string& o : run.overrides) std::cout << "    --set " << o << "\n";
    }
    return 0;
  }
  write_sweep_meta(out.string(), sweep, opt.shard);
  write_sweep_table(out.string(), sweep, mine, records);

  std::string program = opt.program;
  stop_signal = 0;
  auto old_int = std::signal(SIGINT, on_stop_signal);
  auto old_term = std::signal(SIGTERM, on_stop_signal);
  const pid_t parent = getpid();
  std::map<pid_t, Child> running;
  std::size_t next = 0, finished = 0, failed = 0;
  double finished_seconds = 0;
  const auto start = Clock::now();
  auto last_report = Clock::now() - std::chrono::hours(1);
  const bool terminal = isatty(STDOUT_FILENO) != 0;
  bool line_open = false;
  auto report = [&](bool force) {
    if (opt.quiet) return;
    const auto now = Clock::now();
    if (!force && now - last_report < (terminal ? std::chrono::milliseconds(500)
                                                : std::chrono::milliseconds(10000)))
      return;
    last_report = now;
    const double elapsed = std::chrono::duration<double>(now - start).count();
    const std::size_t left = todo.size() - finished;
    std::string eta = "?";
    if (finished > 0) {
      // The work left (mean run time x runs left) less what the running runs have done.
      double work = finished_seconds / finished * static_cast<double>(left);
      for (const auto& [pid, child] : running)
        work -= std::chrono::duration<double>(now - child.start).count();
      eta =
          clock_text(std::max(0.0, work) / std::min<double>(jobs, std::max<std::size_t>(left, 1)));
    }
    if (left == 0) eta = "0:00";
    std::cout << (terminal ? "\r" : "") << "sweep: " << finished << "/" << todo.size() << " done, "
              << failed << " failed, " << running.size() << " running, " << left - running.size()
              << " waiting; " << clock_text(elapsed) << " elapsed, ETA " << eta
              << (terminal ? "\033[K" : "\n") << std::flush;
    line_open = terminal;
  };
  auto say = [&](const std::string& text) {
    if (opt.quiet) return;
    if (line_open) std::cout << "\r\033[K";
    std::cout << text << "\n";
    line_open = false;
    report(true);
  };

  while (next < todo.size() || !running.empty()) {
    while (!stop_signal && next < todo.size() && static_cast<int>(running.size()) < jobs) {
      const std::size_t slot = todo[next++];
      const Run& run = sweep.runs[mine[slot]];
      const fs::path folder = out / run.folder;
      fs::create_directories(folder);
      // A run stopped by a signal (a sweep stopped, a job's time limit) left a checkpoint of
      // this very case: continue from it rather than start over.
      const bool resume = can_continue(folder, run);
      fs::remove(folder / "summary.json");
      write_run_record(folder, sweep, run);
      std::vector<std::string> args{program,
                                    "run",
                                    sweep.base,
                                    "--out",
                                    folder.string(),
                                    "--threads",
                                    std::to_string(threads)};
      for (const std::string& o : run.overrides) {
        args.push_back("--set");
        args.push_back(o);
      }
      if (resume) {
        args.push_back("--restart");
        args.push_back((folder / "checkpoint.h5").string());
      }
      std::vector<char*> argv;
      for (std::string& a : args) argv.push_back(a.data());
      argv.push_back(nullptr);
      const std::string log = (folder / "run.log").string();
      const std::string err = (folder / "stderr.log").string();
      const pid_t pid = fork();
      if (pid < 0) throw std::runtime_error(std::string("fork failed: ") + std::strerror(errno));
      if (pid == 0) {
        // The run stops (writing its checkpoint) when the sweep dies, however it dies.
        prctl(PR_SET_PDEATHSIG, SIGTERM);
        if (getppid() != parent) _exit(130);
        std::signal(SIGINT, SIG_DFL);
        std::signal(SIGTERM, SIG_DFL);
        const int o = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        const int e = open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (o >= 0) dup2(o, STDOUT_FILENO);
        if (e >= 0) dup2(e, STDERR_FILENO);
        execv(program.c_str(), argv.data());
        const char msg[] = "ckpd sweep: cannot start the ckpd program\n";
        [[maybe_unused]] auto n = write(STDERR_FILENO, msg, sizeof msg - 1);
        _exit(127);
      }
      running[pid] = Child{slot, Clock::now()};
      records[slot].status = "running";
    }
    if (stop_signal) {
      for (const auto& [pid, child] : running) kill(pid, SIGTERM);
    }
    int status = 0;
    const pid_t pid = waitpid(-1, &status, WNOHANG);
    if (pid <= 0 || !running.count(pid)) {
      if (stop_signal && running.empty()) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      report(false);
      continue;
    }
    const Child child = running[pid];
    running.erase(pid);
    const Run& run = sweep.runs[mine[child.slot]];
    RunRecord& rec = records[child.slot];
    const fs::path folder = out / run.folder;
    rec.wall_seconds = std::chrono::duration<double>(Clock::now() - child.start).count();
    const auto summary = read_json(folder / "summary.json");
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (summary) collect_metrics(sweep, *summary, rec, warned, opt.quiet);
    if (code == 0 && summary && summary->value("status", "") == "completed") {
      rec.status = "completed";
      rec.message.clear();
    } else if (stop_signal && (code == 130 || WIFSIGNALED(status))) {
      rec.status = "interrupted";
      rec.message = "the sweep was stopped by a signal";
    } else {
      rec.status = "failed";
      if (WIFSIGNALED(status)) {
        rec.message = "killed by signal " + std::to_string(WTERMSIG(status)) + " (" +
                      strsignal(WTERMSIG(status)) + ")";
      } else if (code == 3 && summary && summary->contains("message")) {
        rec.message = "unstable: " + (*summary)["message"].get<std::string>();
      } else {
        rec.message =
            "exit status " + std::to_string(code) + ": " + error_message(folder / "stderr.log");
      }
      ++failed;
      say("run " + run.folder + " (" + run.description + ") failed: " + rec.message);
    }
    if (rec.status != "interrupted") {
      ++finished;
      finished_seconds += *rec.wall_seconds;
    }
    write_sweep_table(out.string(), sweep, mine, records);
    report(false);
  }
  for (RunRecord& rec : records)
    if (rec.status == "running") rec.status = "interrupted";
  write_sweep_table(out.string(), sweep, mine, records);
  report(true);
  if (line_open) std::cout << "\n";
  std::signal(SIGINT, old_int);
  std::signal(SIGTERM, old_term);
  std::size_t completed = 0;
  for (const RunRecord& rec : records) completed += rec.status == "completed";
  if (!opt.quiet)
    std::cout << "sweep: " << completed << " of " << mine.size() << " runs completed, " << failed
              << " failed; table in " << (out / "sweep.csv").string() << "\n";
  if (stop_signal) {
    std::cerr << "ckpd sweep: stopped by a signal; run the same command again to resume\n";
    return 130;
  }
  return completed == mine.size() ? 0 : kSweepRunsFailed;
}

}  // namespace ckpd::sweep
