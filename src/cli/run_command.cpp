#include "src/cli/run_command.hpp"

#include <omp.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "src/case/case_loader.hpp"
#include "src/cli/cli_options.hpp"
#include "src/cli/launch_guard.hpp"
#include "src/cli/rank_agreement.hpp"
#include "src/cli/setup_interrupt.hpp"
#include "src/engine/contact_coupling.hpp"
#include "src/engine/distribution.hpp"
#include "src/engine/force_sharing.hpp"
#include "src/engine/ranks.hpp"
#include "src/engine/scene_warnings.hpp"
#include "src/engine/simulation.hpp"
#include "src/geometry/work_estimate.hpp"
#include "src/input/case_node.hpp"
#include "src/output/beta_report.hpp"
#include "src/output/checkpoint.hpp"
#include "src/output/kernel_report.hpp"
#include "src/output/output_share.hpp"
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
  bool gather_output = false;
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
  else if (sb.sphere_radius > 0)
    os << "DEM sphere of radius " << sb.sphere_radius << " m (inertia 2/5 m R^2)\n";
  else
    os << b.dimension << "D, " << b.size() << " points, dx " << sb.spacing << " m\n";
}

void print_setup(const Simulation& sim, std::ostream& os) {
  for (const SceneBody& sb : sim.whole_scene().bodies) {
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
  os << contact_law_report(sim.whole_scene());
  for (const std::string& w : scene_warnings(sim)) os << "warning: " << w << '\n';
}

// What summary.json records of how the run was made: the command line, the overrides, the
// program's version and build.
nlohmann::ordered_json provenance(const RunOptions& opt) {
  return {{"command_line", command_line()},
          {"overrides", opt.overrides},
          {"working_directory", std::filesystem::current_path().string()},
          {"build", build_json()}};
}

// The exit status and message main() gives an exception that escapes a command (2: bad input).
int status_of(const std::function<void()>& work, std::string& message) {
  try {
    work();
    return 0;
  } catch (const CaseError& e) {
    message = e.what();
    return 2;
  } catch (const CheckpointError& e) {
    message = e.what();
    return 2;
  } catch (const std::invalid_argument& e) {
    message = e.what();
    return 2;
  } catch (const std::exception& e) {
    message = e.what();
    return 1;
  }
}

// Threads per rank when neither --threads nor OMP_NUM_THREADS says: the cores this process may
// use over the ranks started on its node (one each when mpirun binds ranks to cores).
void choose_rank_threads() {
  if (ranks::count() == 1 || std::getenv("OMP_NUM_THREADS") != nullptr) return;
  long long local = 1;
  if (const char* v = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE"))
    local = std::max(1LL, std::atoll(v));
  omp_set_num_threads(static_cast<int>(std::max(1LL, omp_get_num_procs() / local)));
}

// summary.json's account of the ranks: how the points were shared, and what the scheme holds and
// exchanges (`refusal`: why the scene runs on replicated state; empty: distributed memory).
nlohmann::ordered_json decomposition_json(const Scene& scene, const Decomposition& d,
                                          const std::string& refusal) {
  nlohmann::ordered_json per_rank = nlohmann::ordered_json::array();
  double total = 0;
  for (const RankShare& s : d.share) total += s.work;
  const std::uint64_t ghosts = d.ghosts();
  for (std::size_t r = 0; r < d.share.size(); ++r) {
    const RankShare& s = d.share[r];
    per_rank.push_back({{"rank", r},
                        {"points", s.points},
                        {"work_share", total > 0 ? s.work / total : 0.0},
                        {"halo_points", s.ghosts},
                        {"halo_bytes_per_step", halo_bytes_per_step(s.ghosts)}});
  }
  const bool distributed = refusal.empty();
  nlohmann::ordered_json j{
      {"method", "recursive coordinate bisection of the deformable points by interaction work"}};
  j["state"] = distributed
                   ? "distributed: each rank holds the points it owns and their halo (the members "
                     "of its points' families that other ranks own) and evaluates the sets "
                     "centred at its points"
                   : "replicated: every rank holds and integrates the whole scene; each rank "
                     "evaluates the sets centred at its own points (distributed memory does not "
                     "take this scene: " +
                         refusal + ")";
  j["exchange"] =
      distributed
          ? "every step the owners send their ghosts' displacements and velocities (6 doubles a "
            "ghost) and the ranks send the forces their sets put on ghosts back to the owners (3 "
            "doubles a ghost, 4 in a step with energy), which add them in rank order"
          : "every step each rank sends its whole partial force buffer (3 doubles per point of "
            "each deformable body; with energy 1 more per point) to every other rank "
            "(MPI_Allgather), and the buffers are added in rank order";
  j["imbalance"] = d.imbalance();
  j["per_rank"] = per_rank;
  if (distributed) {
    j["halo_points_all_ranks"] = ghosts;
    j["halo_bytes_per_step_all_ranks"] = halo_bytes_per_step(ghosts);
    j["halo_bytes_per_energy_step_all_ranks"] = halo_bytes_per_step(ghosts, true);
  } else {
    const std::size_t sent = shared_force_values(scene, false) * sizeof(double);
    j["sent_bytes_per_rank_per_step"] = sent;
    j["sent_bytes_per_rank_energy_step"] = shared_force_values(scene, true) * sizeof(double);
    j["received_bytes_per_rank_per_step"] = sent * (d.share.size() - 1);
  }
  return j;
}

int run(const RunOptions& opt) {
  // A build with MPI: several processes started together are the ranks of this run.
  if (const auto refusal = parallel_launch_refusal(ranks::built_with_mpi())) {
    std::cerr << "ckpd: error: run: " << *refusal << '\n';
    return 2;
  }
  const ranks::Session session(nullptr, nullptr);
  const int rank = ranks::rank(), rank_count = ranks::count();
  const bool root = rank == 0;
  if (opt.threads > 0)
    omp_set_num_threads(opt.threads);
  else
    choose_rank_threads();
  stop_on_signal_during_setup();
  const auto start = std::chrono::steady_clock::now();
  std::optional<Scene> scene_holder;
  std::optional<DistributedScene> parts;  // a distributed run: this rank's part of the scene
  std::optional<Simulation> sim_holder;
  std::optional<RunDriver> driver_holder;
  Decomposition decomposition;
  std::string refusal;  // several ranks: why the scene runs on replicated state ("": it does not)
  std::ostringstream setup;
  std::string out = opt.out_dir;
  if (out.empty()) out = "runs/" + std::filesystem::path(opt.case_file).stem().string();
  std::string resolved_case;  // several ranks: what each compares with rank 0's
  // Reading the case and building its bodies: each rank alone, no collective.
  auto load = [&]() {
    std::vector<CaseNode::Override> applied;
    YAML::Node resolved = load_case_yaml(opt.case_file, opt.overrides, &applied);
    if (rank_count > 1) resolved_case = YAML::Dump(resolved);
    scene_holder.emplace(load_scene(resolved, opt.case_file, std::move(applied)));
    scene_holder->output.gather_files = opt.gather_output;
  };
  auto set_up = [&]() {
    // Several ranks: each holds its part of the scene (distribution.hpp) or, for a scene that
    // scheme does not take, the whole scene, evaluating the sets centred at its own points
    // (force_sharing.hpp).
    if (rank_count > 1) {
      refusal = distribution_refusal(*scene_holder);
      try {
        if (refusal.empty()) {
          parts.emplace(distribute_scene(*scene_holder, rank, rank_count));
          decomposition = parts->distribution->decomposition();
        } else {
          decomposition = share_force_work(*scene_holder, rank, rank_count);
        }
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(opt.case_file + ": " + e.what() + " (mpirun -np " +
                                    std::to_string(rank_count) + ")");
      }
    }
    if (parts) {
      sim_holder.emplace(parts->local, std::move(parts->distribution));
      sim_holder->set_whole_scene(*scene_holder);
    } else {
      sim_holder.emplace(*scene_holder);
    }
    Simulation& sim = *sim_holder;
    if (!opt.restart.empty()) read_checkpoint(opt.restart, sim);
    const double setup_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // From here a signal finishes the step, writes a checkpoint and stops (the loop below).
    stop_requested = 0;
    std::signal(SIGINT, request_stop);
    std::signal(SIGTERM, request_stop);
    print_setup(sim, setup);
    if (rank_count > 1) {
      setup << "MPI: " << rank_count << " ranks x " << omp_get_max_threads()
            << " threads, points shared by recursive coordinate bisection (imbalance "
            << decomposition.imbalance() << "); ";
      if (refusal.empty()) {
        const std::uint64_t ghosts = decomposition.ghosts();
        setup << "distributed memory: each rank holds its points and their halo, " << ghosts
              << " halo points, " << format_bytes(halo_bytes_per_step(ghosts))
              << " of halo messages per step in all; frames and checkpoints "
              << output_files_text(true, opt.gather_output) << "\n";
      } else {
        setup << "state replicated on every rank (distributed memory does not take this scene: "
              << refusal << ")\n";
      }
    }
    if (!opt.quiet && root) std::cout << setup.str() << std::flush;
    if (opt.quiet && root)  // warnings are not progress: --quiet keeps them, on stderr
      for (const std::string& w : scene_warnings(sim)) std::cerr << "ckpd: warning: " << w << '\n';

    RunDriverOptions driver_options;
    driver_options.out = out;  // rank 0 writes the files (the ranks share frames, checkpoints)
    driver_options.restarted_from = opt.restart;
    driver_options.progress = !opt.quiet && root;
    driver_options.start = start;
    driver_options.setup_seconds = setup_seconds;
    driver_options.log_header.push_back(version_line());
    driver_options.log_header.push_back("command: " + command_line());
    for (const std::string& o : opt.overrides)
      driver_options.log_header.push_back("override: --set " + o);
    driver_options.log_header.push_back(setup.str());
    driver_options.provenance = provenance(opt);
    if (rank_count > 1) {
      driver_options.decomposition = decomposition_json(*scene_holder, decomposition, refusal);
      driver_options.decomposition["frames_and_checkpoints"] =
          output_files_text(parts.has_value(), opt.gather_output);
    }
    // An output folder that cannot be made or written is bad input too (exit 2), found before
    // any step.
    try {
      driver_holder.emplace(sim, driver_options);
    } catch (const std::runtime_error& e) {
      throw CaseError(std::string("--out ") + e.what());
    }
  };
  if (rank_count == 1) {
    load();
    set_up();
  } else {
    // Every rank passes each of these points: a failure on any of them (bad input on all, a
    // refusal on one node only, an output folder only rank 0 cannot make) is printed once and
    // every rank exits with it. The ranks agree on the loaded case before any collective.
    std::string message;
    int status = ranks::agree_on_failure(status_of(load, message), message);
    if (status == 0)
      status = agree_on_loaded_case(
          {resolved_case, &*scene_holder, out, opt.restart, opt.gather_output});
    if (status == 0) status = ranks::agree_on_failure(status_of(set_up, message), message);
    if (status != 0) return status;
  }
  Simulation& sim = *sim_holder;
  RunDriver& driver = *driver_holder;
  try {
    while (!driver.finished()) {
      driver.step();
      // One rank's signal stops every rank after the same step.
      if (ranks::any(stop_requested != 0)) {
        driver.write_checkpoint();
        const std::string message = "interrupted by a signal at step " +
                                    std::to_string(sim.step()) + "; continue with --restart " +
                                    out + "/checkpoint.h5";
        driver.stop("interrupted", message);
        if (root) std::cerr << "ckpd: " << message << '\n';
        return 130;
      }
    }
  } catch (const TunnellingError& e) {
    // Every rank throws the same error at the same step (the guards are collectives).
    driver.stop("tunnelling", e.what());
    if (root)
      std::cerr << "ckpd: " << e.what() << "\nckpd: results up to that step are in " << out << '\n';
    return 3;
  } catch (const InstabilityError& e) {
    driver.stop("unstable", e.what());
    if (root)
      std::cerr << "ckpd: " << e.what() << "\nckpd: results up to that step are in " << out << '\n';
    return 3;
  } catch (const std::exception& e) {
    if (rank_count == 1) throw;
    // Seen by this rank only (a file rank 0 could not write): the others cannot go on.
    std::cerr << "ckpd: error: rank " << rank << ": " << e.what() << std::endl;
    ranks::abort_all(1);
  }
  driver.stop("completed", "");
  if (!opt.quiet && root) {
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
  cmd->add_flag("--gather-output", opt->gather_output,
                "MPI on distributed memory: rank 0 gathers the points and writes the field frames "
                "and checkpoints alone (a file system without MPI-IO locking, such as NFS); by "
                "default every rank writes its points into them where HDF5 is parallel");
  cmd->callback([opt, &exit_status]() { exit_status = run(*opt); });
}

}  // namespace ckpd
