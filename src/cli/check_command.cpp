#include "src/cli/check_command.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>

#include "src/case/case_loader.hpp"
#include "src/cli/cli_options.hpp"
#include "src/cli/setup_interrupt.hpp"
#include "src/engine/contact_coupling.hpp"
#include "src/engine/decomposition.hpp"
#include "src/engine/distribution.hpp"
#include "src/engine/force_sharing.hpp"
#include "src/engine/scene_warnings.hpp"
#include "src/engine/simulation.hpp"
#include "src/geometry/work_estimate.hpp"
#include "src/output/kernel_report.hpp"
#include "src/output/output_share.hpp"
#include "src/output/run_output.hpp"

namespace ckpd {

// Bytes the body's own arrays hold: state and reference vectors, per-point constants, the CSR
// family and its intact flags, the general path's adjacency rows where the body has them.
// (Kernel scratch adds threads x points x 32 bytes.)
double body_megabytes(const Body& b) {
  const double n = static_cast<double>(b.size());
  const double per_point = 6 * sizeof(Vec3)      // X, u, v, a, b_ext, b
                           + 8 * sizeof(double)  // volume, beta, dv1-3, k, W, (spare)
                           + 2 * sizeof(std::uint32_t) + sizeof(std::size_t) + 1;
  const double per_bond_entry = sizeof(std::uint32_t) + 1;
  const double rows = b.upper_rows ? static_cast<double>(b.upper_rows->bytes()) : 0.0;
  return (n * per_point + static_cast<double>(b.family.bond_entries()) * per_bond_entry + rows) /
         1e6;
}

namespace {

struct CheckOptions {
  std::string case_file;
  std::vector<std::string> overrides;
  int steps = 3;
  int threads = 0;
  int ranks = 0;            // 0: no decomposition report
  bool cost_ratio = false;  // time the far field's linear and exact steps (far_field_cost)
};

std::string megabytes_text(double mb) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(1) << mb << " MB";
  return s.str();
}

// A mesh body: its surface, and for a sampled body how well the points fill it.
void print_mesh(const MeshInfo& m, const Body& b) {
  std::cout << "    mesh " << m.file << ": " << m.triangles << " triangles, box (" << m.lo.x()
            << ", " << m.lo.y() << ", " << m.lo.z() << ") to (" << m.hi.x() << ", " << m.hi.y()
            << ", " << m.hi.z() << ") m, "
            << (m.closed ? std::string("closed")
                         : "open (" + std::to_string(m.open_edges) + " open edges)");
  if (m.closed) std::cout << ", mesh volume " << m.mesh_volume << " m^3";
  if (m.wall) {
    std::cout << "; a mesh wall: no points inside (its 6 carrier points hold its motion)\n";
    return;
  }
  double sampled = 0;
  for (double v : b.volume) sampled += v;
  std::cout << ", sampled volume " << sampled << " m^3";
  if (m.closed && m.mesh_volume > 0)
    std::cout << " (" << std::showpos << 100 * (sampled / m.mesh_volume - 1) << std::noshowpos
              << " %)";
  std::cout << ", " << b.size() << " points\n";
}

// What a run on `ranks` MPI ranks would hold per rank (src/engine/decomposition.hpp), and what
// the scheme it would run on exchanges per step (distribution.hpp or force_sharing.hpp).
void print_decomposition(const Scene& scene, int ranks) {
  std::vector<const Body*> bodies;
  std::vector<bool> rigid;
  for (const SceneBody& sb : scene.bodies) {
    bodies.push_back(&sb.body);
    rigid.push_back(sb.rigid.has_value());
  }
  const Decomposition d = decompose(bodies, rigid, ranks);
  double total = 0;
  for (const RankShare& r : d.share) total += r.work;
  const std::uint64_t ghosts = d.ghosts();
  const std::string refusal = distribution_refusal(scene);
  std::cout << "decomposition over " << ranks
            << " ranks (recursive coordinate bisection by interaction work): imbalance "
            << d.imbalance() << " (largest rank's work over the mean), " << ghosts
            << " halo points\n";
  if (refusal.empty()) {
    std::cout << "  distributed memory: each rank holds its points and their halo; per step "
              << format_bytes(halo_bytes_per_step(ghosts)) << " of halo messages in all ("
              << format_bytes(halo_bytes_per_step(ghosts, true)) << " in a step with energy)\n";
    if (has_contact_work(scene))
      std::cout << "  contact on distributed memory: each rank takes as contact ghosts the points "
                   "other ranks own within l_c + skin of its own, chosen during the run from the "
                   "current positions (48 bytes a ghost per step; summary.json counts them)\n";
    std::cout << "  field frames and checkpoints: " << output_files_text(true, false)
              << " (ckpd run --gather-output: " << output_files_text(true, true) << ")\n";
  } else {
    std::size_t sent = 0;
    for (const SceneBody& sb : scene.bodies)
      if (force_work_can_be_shared(sb))
        sent += shared_force_values(sb.body, false) * sizeof(double);
    std::cout << "  replicated state (distributed memory does not take this scene: " << refusal
              << "): every rank holds the whole scene and sends its whole partial force buffer, "
              << format_bytes(sent) << ", to every other rank per step\n";
  }
  for (std::size_t r = 0; r < d.share.size(); ++r) {
    const RankShare& s = d.share[r];
    std::cout << "  rank " << r << ": " << s.points << " points, " << std::fixed
              << std::setprecision(1) << 100 * s.work / total << std::defaultfloat
              << std::setprecision(6) << " % of the work, " << s.ghosts << " halo points";
    if (refusal.empty())
      std::cout << ", " << format_bytes(halo_bytes_per_step(s.ghosts))
                << " received and sent back per step";
    std::cout << '\n';
  }
}

// Wall seconds per step of `steps` steps (at least one).
double seconds_per_step(Simulation& sim, int steps) {
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < steps; ++k) sim.advance(false);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / steps;
}

// The far field's cost ratio c (issue 20's speed-up bound): `steps` steps with every far-field
// point that can be linear made linear (the tolerance lifted, the sticky exact flags cleared;
// the classification keeps points with a failed bond near them and, corotated, families that
// span no volume exact: a fraction f0, taken out of c below), then `steps` steps with the far
// field off (every body exact). A step with a fraction f of its points exact then costs about
// f + (1 - f) c of an exact step, so the far field can be at most 1 / (f + (1 - f) c) times
// faster. The probe advances the check's own state only (check writes nothing), within the
// case's planned steps. Returns the exit status as check does.
int far_field_cost(Simulation& sim, Scene& scene, int steps, double timed_per_step) {
  const double timed_fraction = sim.exact_fraction();
  for (SceneBody& sb : scene.bodies) {
    if (!sb.far_field) continue;
    FarField& ff = *sb.far_field;
    ff.tolerance = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < ff.exact.size(); ++i)
      ff.exact[i] = ff.corotated && ff.shape_inverse[i].isZero() ? 1 : 0;
  }
  double linear = 0, exact = 0, linear_fraction = 0;
  try {
    linear = seconds_per_step(sim, steps);
    linear_fraction = sim.exact_fraction();
    for (SceneBody& sb : scene.bodies) sb.far_field.reset();
    exact = seconds_per_step(sim, steps);
  } catch (const InstabilityError& e) {
    std::cerr << "ckpd: " << e.what() << "\nckpd: check: the case is not stable within the "
              << steps << " steps of the far field's cost probe\n";
    return 3;
  }
  if (!(linear_fraction < 1)) {
    std::cout << "far field cost (--cost-ratio): every far-field point stays exact with the "
                 "tolerance lifted (damage near all of them): no linear cost to measure\n";
    return 0;
  }
  // The probe's own exact points (near damage) are taken out: linear = (f0 + (1 - f0) c) exact.
  const double c = (linear / exact - linear_fraction) / (1 - linear_fraction);
  auto bound = [c](double f) { return 1 / (f + (1 - f) * c); };
  std::cout << "far field cost (--cost-ratio), over " << steps << " steps each: " << linear
            << " s per step with the tolerance lifted (exact fraction " << linear_fraction
            << ": only points near damage exact), " << exact
            << " s per step with the far field off; cost ratio c = " << c
            << "\n  speed-up bound 1 / (f + (1 - f) c): " << bound(timed_fraction)
            << "x at the timed steps' exact fraction f = " << timed_fraction
            << " (measured there: " << exact / timed_per_step << "x); " << bound(0.1) << "x, "
            << bound(0.2) << "x, " << bound(0.3) << "x, " << bound(0.5)
            << "x at f = 0.1, 0.2, 0.3, 0.5\n";
  return 0;
}

// Returns the exit status: 0, or 3 when a timed step goes unstable (as `run` would).
int check(const CheckOptions& opt) {
  if (opt.threads > 0) omp_set_num_threads(opt.threads);
  stop_on_signal_during_setup();  // check writes nothing: a signal stops it at any point
  const auto start = std::chrono::steady_clock::now();
  Scene scene = load_scene(opt.case_file, opt.overrides);
  Simulation sim(scene);
  const double setup =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "case " << opt.case_file << ": valid\n";
  double megabytes = 0;
  for (const SceneBody& sb : scene.bodies) {
    const Body& b = sb.body;
    megabytes += body_megabytes(b);
    if (sb.rigid) {
      // A rigid body has no bonds, horizon or kernel: its line says what it is.
      std::cout << "  body '" << b.name << "': rigid, "
                << (sb.rigid->prescribed() ? "prescribed" : "free") << " motion, ";
      if (sb.rigid->prescribed() && !(sb.rigid->mass() > 0))
        std::cout << "no mass (its motion needs none)";
      else
        std::cout << "mass " << sb.rigid->mass() << (b.dimension == 2 ? " kg/m" : " kg");
      if (sb.wall && sb.mesh)
        std::cout << ", mesh wall of " << sb.mesh->triangles << " triangles (" << b.size()
                  << " carrier points)\n";
      else if (sb.sphere_radius > 0)
        std::cout << ", DEM sphere of radius " << sb.sphere_radius << " m (inertia 2/5 m R^2)\n";
      else
        std::cout << ", " << b.dimension << "D, " << b.size() << " points, dx " << sb.spacing
                  << " m\n";
      if (sb.mesh) print_mesh(*sb.mesh, b);
      continue;
    }
    std::cout << "  body '" << b.name << "': " << b.dimension << "D"
              << ", " << b.size() << " points, " << b.bond_count() << " bonds, N2 "
              << b.total_two_neighbour() << ", N3 " << b.total_three_neighbour()
              << " (ordered), dx " << sb.spacing << " m, horizon " << b.horizon << " m, mass "
              << b.mass() << (b.dimension == 2 ? " kg/m" : " kg") << ", ~"
              << megabytes_text(body_megabytes(b)) << " of body data\n";
    std::cout << "    kernel: " << kernel_path_note(b) << '\n';
    if (sb.far_field) {
      megabytes += static_cast<double>(sb.far_field->op.bytes()) / 1e6;
      std::cout << "    far field: tolerance " << sb.far_field->tolerance << ", linear operator "
                << megabytes_text(static_cast<double>(sb.far_field->op.bytes()) / 1e6) << " ("
                << sb.far_field->op.classes << " row classes for " << b.size()
                << " points, one 3 x 3 block per family member and class; "
                << sb.far_field->op.assembled
                << " assembled, the others turned by a lattice symmetry), ";
      if (sb.far_field->corotated) {
        const double rotations = static_cast<double>((sb.far_field->shape_inverse.size() +
                                                      sb.far_field->rotation.size()) *
                                                     sizeof(Eigen::Matrix3d)) /
                                 1e6;
        megabytes += rotations;
        std::cout << "corotated (shape tensors and rotations " << megabytes_text(rotations)
                  << "), ";
      }
      std::cout << "exact at set-up: " << sb.far_field->exact_count << " of " << b.size()
                << " points\n";
    }
    if (sb.mesh) print_mesh(*sb.mesh, b);
  }
  const StepChoice& s = sim.step_choice();
  const std::vector<double> contact = contact_stiffness_bounds(scene);
  std::size_t limiting = 0;
  for (std::size_t i = 0; i < scene.bodies.size(); ++i)
    if (scene.bodies[i].body.name == s.limiting_body) limiting = i;
  const Body& lb = scene.bodies[limiting].body;
  const StiffnessTerms terms = stiffness_terms(lb, s.limiting_point);
  const double contact_k = contact.empty() ? 0.0 : contact[limiting];
  const double largest = std::max({terms.bonds, terms.pairs, terms.triples, contact_k});
  const char* term = largest == terms.bonds     ? "bonds (one-neighbour)"
                     : largest == terms.pairs   ? "two-neighbour interactions"
                     : largest == terms.triples ? "three-neighbour interactions"
                                                : "contact";
  std::cout << "stable step: estimate " << s.estimate << " s, limited by body '" << s.limiting_body
            << "', point " << s.limiting_point << " at (" << s.limiting_position.x() << ", "
            << s.limiting_position.y() << ", " << s.limiting_position.z()
            << "); largest term: " << term << " (stiffness bounds: bonds " << terms.bonds
            << ", pairs " << terms.pairs << ", triples " << terms.triples << ", contact "
            << contact_k << " N/m^4)\n";
  std::cout << "time step: " << s.dt << " s (" << s.safety << " x estimate"
            << (s.user_dt ? ", from the case" : "") << "), " << sim.planned_steps() << " steps\n";
  std::cout
      << "step mode: "
      << (sim.adaptive()
              ? "adaptive (time.step_mode: adaptive): after each force evaluation the next step "
                "is min(dt, time.safety x the stable step at the current state) for bodies "
                "whose strain measure stiffens in compression (m <= 0); the step count is "
                "the estimate at dt"
              : "fixed (dt for the whole run; bodies with m <= 0 are guarded at the current "
                "state after every step)")
      << "\n";
  if (std::isfinite(s.speed_step)) std::cout << "  " << contact_speed_note(s) << '\n';
  std::cout << contact_law_report(scene);
  for (const std::string& w : scene_warnings(sim)) std::cout << "warning: " << w << '\n';
  if (opt.ranks > 0) print_decomposition(scene, opt.ranks);
  std::cout << "memory: ~" << megabytes_text(megabytes) << " of body data; peak RSS after set-up "
            << megabytes_text(peak_rss_mb()) << "\n";

  const int steps = static_cast<int>(std::min<long long>(opt.steps, sim.planned_steps()));
  if (steps <= 0) {
    std::cout << "set-up took " << setup << " s; no steps to time\n";
    if (opt.cost_ratio) std::cout << "far field cost (--cost-ratio): needs timed steps\n";
    return 0;
  }
  const double bound_before = sim.stable_step_seconds();  // the set-up's own evaluation
  const auto t0 = std::chrono::steady_clock::now();
  try {
    // The last timed step checks the energy too: an instability that the speed guard has not
    // caught yet is an energy blow-up (run checks it at every history row).
    for (int k = 0; k < steps; ++k) sim.advance(k + 1 == steps);
  } catch (const InstabilityError& e) {  // TunnellingError too
    std::cerr << "ckpd: " << e.what() << "\nckpd: check: the case is not stable within the "
              << steps << " timed steps\n";
    return 3;
  }
  const double per_step =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / steps;
  if (sim.stable_step_seconds() > bound_before) {
    std::cout << "  of which " << (sim.stable_step_seconds() - bound_before) / steps
              << " s per step in the current-state stable-step bound (m <= 0)";
    if (sim.adaptive())
      std::cout << "; smallest step so far " << std::min(s.dt, sim.smallest_step()) << " s";
    std::cout << "\n";
  }
  const double projected = setup + per_step * static_cast<double>(sim.planned_steps());
  std::cout << "timing: set-up " << setup << " s, " << per_step << " s per step over " << steps
            << " steps at " << omp_get_max_threads() << " threads; projected run time " << projected
            << " s (" << projected / 3600 << " h)\n";
  if (sim.has_far_field())
    std::cout << "  far field: fraction of its points exact after the timed steps "
              << sim.exact_fraction()
              << "; the projection holds while it stays there (it grows as damage and strain "
                 "spread: exact points are exact for good)\n";
  if (opt.cost_ratio) {
    if (!sim.has_far_field()) {
      std::cout << "far field cost (--cost-ratio): no body of this case has a far field\n";
      return 0;
    }
    // As many probe steps of each kind as the timed steps, as far as the case's steps allow.
    const int probe =
        static_cast<int>(std::min<long long>(steps, (sim.planned_steps() - steps) / 2));
    if (probe <= 0) {
      std::cout << "far field cost (--cost-ratio): the case plans too few steps for the probe ("
                << sim.planned_steps() << " in all, " << steps << " timed)\n";
      return 0;
    }
    return far_field_cost(sim, scene, probe, per_step);
  }
  return 0;
}

}  // namespace

void add_check_command(CLI::App& app, int& exit_status) {
  auto opt = std::make_shared<CheckOptions>();
  CLI::App* cmd = app.add_subcommand(
      "check", "Validate a case without running it: sizes, memory, stable step, projected time");
  cmd->add_option("case", opt->case_file, "case file (YAML)")->required();
  cmd->add_option("--set", opt->overrides, "override a case value: key.path=value (repeatable)");
  cmd->add_option("--steps", opt->steps, "steps to time for the projection (default 3)")
      ->check(CLI::NonNegativeNumber);
  add_threads_option(*cmd, opt->threads);
  cmd->add_flag("--cost-ratio", opt->cost_ratio,
                "with a far field: after the timed steps, time as many steps with every point "
                "linear and as many exact, and print the cost ratio c and the speed-up bound "
                "1 / (f + (1 - f) c)");
  cmd->add_option("--ranks", opt->ranks,
                  "report the decomposition a run on this many MPI ranks would use: points, "
                  "work share, halo points and bytes exchanged per step for each rank")
      ->check(CLI::Range(1, 1 << 20));
  cmd->callback([opt, &exit_status]() { exit_status = check(*opt); });
}

}  // namespace ckpd
