#include "src/cli/run_command.hpp"

#include <omp.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include "src/engine/contact_coupling.hpp"
#include "src/engine/simulation.hpp"
#include "src/output/beta_report.hpp"
#include "src/output/checkpoint.hpp"
#include "src/output/field_writer.hpp"
#include "src/output/kernel_report.hpp"
#include "src/output/progress.hpp"
#include "src/output/run_output.hpp"
#include "src/scene/case_loader.hpp"

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

void print_setup(const Simulation& sim, std::ostream& os) {
  for (const SceneBody& sb : sim.scene().bodies) {
    const Body& b = sb.body;
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
     << " x estimate -> dt " << s.dt << " s, " << sim.planned_steps() << " steps\n";
  if (std::isfinite(s.speed_step)) os << "  " << contact_speed_note(s) << '\n';
  os << contact_law_report(sim.scene());
}

int run(const RunOptions& opt) {
  if (opt.threads > 0) omp_set_num_threads(opt.threads);
  const auto start = std::chrono::steady_clock::now();
  Scene scene = load_scene(opt.case_file, opt.overrides);
  Simulation sim(scene);
  if (!opt.restart.empty()) read_checkpoint(opt.restart, sim);
  const long long resume = opt.restart.empty() ? -1 : sim.step();
  const double setup_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!opt.quiet) print_setup(sim, std::cout);

  std::string out = opt.out_dir;
  if (out.empty()) out = "runs/" + std::filesystem::path(opt.case_file).stem().string();
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec || !std::filesystem::is_directory(out))
    throw std::runtime_error(out + ": cannot create the output directory");
  HistoryWriter history(out + "/history.csv", resume);
  // Summaries of earlier runs in this folder must not pass for this one's.
  std::filesystem::remove(out + "/summary.json", ec);

  const long long total = sim.planned_steps();
  const long long interval = scene.output.history_interval > 0
                                 ? scene.output.history_interval
                                 : std::max<long long>(1, total / 200);
  std::optional<FieldWriter> fields;
  if (scene.output.writes_fields()) fields.emplace(out, scene.output.fields, resume);
  const OutputSettings& o = scene.output;
  const double dt = sim.step_choice().dt;
  // Frame k is written at the first step whose time reaches k * field_time_interval.
  auto frame_due = [&](long long step, double time) {
    if (!fields) return false;
    if (o.field_interval > 0) return step % o.field_interval == 0;
    return time >= static_cast<double>(fields->frames()) * o.field_time_interval - 1e-9 * dt;
  };
  if (resume < 0) history.write_row(sim);
  if (fields && (resume < 0 || fields->frames() == 0)) fields->write_frame(sim);
  const std::string checkpoint = out + "/checkpoint.h5";
  stop_requested = 0;
  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);
  auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  auto summary = [&](const std::string& status, const std::string& message) {
    auto j = make_summary(sim, status, message, seconds());
    j["setup_seconds"] = setup_seconds;
    const long long stepped = sim.step() - std::max(resume, 0LL);  // by this process
    j["seconds_per_step"] =
        stepped > 0 ? (seconds() - setup_seconds) / static_cast<double>(stepped) : 0.0;
    j["threads"] = omp_get_max_threads();
    if (fields) j["field_frames"] = fields->frames();
    if (!opt.restart.empty()) j["restarted_from"] = {{"file", opt.restart}, {"step", resume}};
    return j;
  };
  ProgressReporter progress(!opt.quiet, total);
  // Model breakdown (inverted tetrahedra/triangles) is reported once, when first seen.
  bool inversion_reported = false;
  auto report_inversion = [&] {
    if (inversion_reported || sim.first_inversion().step < 0) return;
    inversion_reported = true;
    progress.finish();
    std::cerr << "ckpd: warning: " << inversion_warning(sim) << '\n';
  };
  report_inversion();
  try {
    while (sim.step() < total) {
      const long long next = sim.step() + 1;
      const bool last = next == total;
      const bool row = next % interval == 0 || last;
      const bool frame = frame_due(next, static_cast<double>(next) * dt) || (fields && last);
      sim.advance(row || (frame && fields->needs_energy()));
      if (row) history.write_row(sim);
      report_inversion();
      if (frame) fields->write_frame(sim);
      progress.update(sim);
      const bool interval_checkpoint = scene.output.checkpoint_interval > 0 &&
                                       sim.step() % scene.output.checkpoint_interval == 0;
      if (interval_checkpoint || stop_requested) write_checkpoint(checkpoint, sim);
      if (stop_requested) {
        progress.finish();
        if (!row) history.write_row(sim);
        const std::string message = "interrupted by a signal at step " +
                                    std::to_string(sim.step()) + "; continue with --restart " +
                                    checkpoint;
        write_json(out + "/summary.json", summary("interrupted", message));
        std::cerr << "ckpd: " << message << '\n';
        return 130;
      }
    }
  } catch (const TunnellingError& e) {
    progress.finish();
    history.write_row(sim);
    write_json(out + "/summary.json", summary("tunnelling", e.what()));
    std::cerr << "ckpd: " << e.what() << "\nckpd: results up to that step are in " << out << '\n';
    return 3;
  } catch (const InstabilityError& e) {
    progress.finish();
    history.write_row(sim);
    write_json(out + "/summary.json", summary("unstable", e.what()));
    std::cerr << "ckpd: " << e.what() << "\nckpd: results up to that step are in " << out << '\n';
    return 3;
  }
  progress.finish();
  write_json(out + "/summary.json", summary("completed", ""));
  if (!opt.quiet) {
    std::cout << "completed " << sim.step() << " steps in " << seconds() << " s; peak RSS "
              << peak_rss_mb() << " MB; max damage " << sim.max_damage() << "; results in " << out
              << '\n';
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
  cmd->add_option("--threads", opt->threads, "OpenMP threads (default: all cores)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--restart", opt->restart,
                  "continue from a checkpoint of this case (DIR/checkpoint.h5, written every "
                  "output.checkpoint_interval steps and on SIGINT/SIGTERM)");
  cmd->add_flag("--quiet", opt->quiet, "print nothing but errors");
  cmd->callback([opt, &exit_status]() { exit_status = run(*opt); });
}

}  // namespace ckpd
