#include "src/cli/run_command.hpp"

#include <omp.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "src/case/case_loader.hpp"
#include "src/cli/cli_options.hpp"
#include "src/cli/launch_guard.hpp"
#include "src/cli/setup_interrupt.hpp"
#include "src/engine/contact_coupling.hpp"
#include "src/engine/simulation.hpp"
#include "src/output/beta_report.hpp"
#include "src/output/checkpoint.hpp"
#include "src/output/kernel_report.hpp"
#include "src/output/run_driver.hpp"

namespace ckpd {

namespace {

struct RunOptions {
  std::string case_file;
  std::string out_dir;
  std::vector<std::string> overrides;
  std::string restart;
  int threads = 0;
  bool quiet = false;
};

// Set by SIGINT/SIGTERM: the run finishes its step, writes a checkpoint and stops.
volatile std::sig_atomic_t stop_requested = 0;
extern "C" void request_stop(int) {
  stop_requested = 1;
}

// A rigid body has no interactions: its line says what it is instead of zero constants.
void print_rigid_setup(const SceneBody& sb, std::ostream& os) {
  const Body& b = sb.body;
  os << "body '" << b.name << "': rigid, " << (sb.rigid->prescribed() ? "prescribed" : "free")
     << " motion, mass " << sb.rigid->mass() << " kg, ";
  if (sb.wall && sb.mesh)
    os << "mesh wall of " << sb.mesh->triangles << " triangles (" << b.size()
       << " carrier points)\n";
  else
    os << b.dimension << "D, " << b.size() << " points, dx " << sb.spacing << " m\n";
}

void print_setup(const Simulation& sim, std::ostream& os) {
  for (const SceneBody& sb : sim.scene().bodies) {
    const Body& b = sb.body;
    if (sb.rigid) {
      print_rigid_setup(sb, os);
      continue;
    }
    os << "body '" << b.name << "': " << b.dimension << "D, " << b.size() << " points, "
       << b.bond_count() << " bonds, N2 " << b.total_two_neighbour() << ", N3 "
       << b.total_three_neighbour() << ", dx " << sb.spacing << " m, horizon " << b.horizon
       << " m, C1 " << b.constants.c1 << ", C2 " << b.constants.c2 << ", C3 " << b.constants.c3
       << ", critical stretch " << (b.damage_enabled ? std::to_string(b.critical_stretch) : "none")
       << (b.damage_enabled ? ", damage rule " + to_string(b.damage_rule) : "") << '\n';
    if (const std::string note = beta_setup_note(b); !note.empty()) os << note << '\n';
    os << "  kernel: " << kernel_path_note(b) << '\n';
  }
  const StepChoice& s = sim.step_choice();
  os << "time step: estimate " << s.estimate << " s (body '" << s.limiting_body << "', point "
     << s.limiting_point << "), " << (s.user_dt ? "case dt " : "safety ") << s.safety
     << " x estimate -> dt " << s.dt << " s, " << sim.planned_steps() << " steps";
  if (sim.adaptive())
    os << " at this dt (time.step_mode: adaptive: each step min(dt, safety x the current stable "
          "step); the first "
       << sim.step_size(1) << " s)";
  else if (const double last = sim.step_size(sim.planned_steps()); last != s.dt)
    os << " (the last one " << last << " s: the run ends exactly at time.end)";
  os << '\n';
  if (std::isfinite(s.speed_step)) os << "  " << contact_speed_note(s) << '\n';
  os << contact_law_report(sim.scene());
}

// What summary.json records of how the run was made: the command line, the overrides, the
// program's version and build.
nlohmann::ordered_json provenance(const RunOptions& opt) {
  return {{"command_line", command_line()},
          {"overrides", opt.overrides},
          {"working_directory", std::filesystem::current_path().string()},
          {"build", build_json()}};
}

int run(const RunOptions& opt) {
  if (const auto refusal = parallel_launch_refusal()) {
    std::cerr << "ckpd: error: run: " << *refusal << '\n';
    return 2;
  }
  if (opt.threads > 0) omp_set_num_threads(opt.threads);
  stop_on_signal_during_setup();
  const auto start = std::chrono::steady_clock::now();
  Scene scene = load_scene(opt.case_file, opt.overrides);
  Simulation sim(scene);
  if (!opt.restart.empty()) read_checkpoint(opt.restart, sim);
  const double setup_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // From here a signal finishes the step, writes a checkpoint and stops (the loop below).
  stop_requested = 0;
  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);
  std::ostringstream setup;
  print_setup(sim, setup);
  if (!opt.quiet) std::cout << setup.str();

  std::string out = opt.out_dir;
  if (out.empty()) out = "runs/" + std::filesystem::path(opt.case_file).stem().string();
  RunDriverOptions driver_options;
  driver_options.out = out;
  driver_options.restarted_from = opt.restart;
  driver_options.progress = !opt.quiet;
  driver_options.start = start;
  driver_options.setup_seconds = setup_seconds;
  driver_options.log_header.push_back(version_line());
  driver_options.log_header.push_back("command: " + command_line());
  for (const std::string& o : opt.overrides)
    driver_options.log_header.push_back("override: --set " + o);
  driver_options.log_header.push_back(setup.str());
  driver_options.provenance = provenance(opt);
  // An output folder that cannot be made or written is bad input too (exit 2), found before
  // any step.
  std::optional<RunDriver> driver_holder;
  try {
    driver_holder.emplace(sim, driver_options);
  } catch (const std::runtime_error& e) {
    throw CaseError(std::string("--out ") + e.what());
  }
  RunDriver& driver = *driver_holder;
  try {
    while (!driver.finished()) {
      driver.step();
      if (stop_requested) {
        driver.write_checkpoint();
        const std::string message = "interrupted by a signal at step " +
                                    std::to_string(sim.step()) + "; continue with --restart " +
                                    driver.checkpoint_path();
        driver.stop("interrupted", message);
        std::cerr << "ckpd: " << message << '\n';
        return 130;
      }
    }
  } catch (const TunnellingError& e) {
    driver.stop("tunnelling", e.what());
    std::cerr << "ckpd: " << e.what() << "\nckpd: results up to that step are in " << out << '\n';
    return 3;
  } catch (const InstabilityError& e) {
    driver.stop("unstable", e.what());
    std::cerr << "ckpd: " << e.what() << "\nckpd: results up to that step are in " << out << '\n';
    return 3;
  }
  driver.stop("completed", "");
  if (!opt.quiet) {
    std::cout << "completed " << sim.step() << " steps to t = " << sim.time() << " s in "
              << driver.seconds() << " s; peak RSS " << peak_rss_mb() << " MB; max damage "
              << sim.max_damage() << "; results in " << out << '\n';
  }
  return 0;
}

}  // namespace

void add_run_command(CLI::App& app, int& exit_status) {
  auto opt = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand("run", "Run a case file");
  cmd->add_option("case", opt->case_file, "case file (YAML)")->required();
  cmd->add_option("--out", opt->out_dir, "output directory (default: runs/<case name>)");
  cmd->add_option("--set", opt->overrides, "override a case value: key.path=value (repeatable)");
  add_threads_option(*cmd, opt->threads);
  cmd->add_option("--restart", opt->restart,
                  "continue from a checkpoint of this case (DIR/checkpoint.h5, written every "
                  "output.checkpoint_interval steps and on SIGINT/SIGTERM)");
  cmd->add_flag("--quiet", opt->quiet, "print nothing but errors");
  cmd->callback([opt, &exit_status]() { exit_status = run(*opt); });
}

}  // namespace ckpd
