#include "src/engine/simulation.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "base/parallel_policy.hpp"
#include "bodies/current_stiffness.hpp"
#include "bodies/damage.hpp"
#include "bodies/far_field.hpp"
#include "bodies/state_based_model.hpp"
#include "bodies/symmetric_kernel.hpp"
#include "src/engine/contact_coupling.hpp"
#include "src/engine/contact_ghosts.hpp"
#include "src/engine/distribution.hpp"
#include "src/engine/force_sharing.hpp"

namespace ckpd {

namespace {

std::string format_position(const Vec3& p, int dimension) {
  std::ostringstream s;
  s << "(" << p.x() << ", " << p.y();
  if (dimension == 3) s << ", " << p.z();
  s << ") m";
  return s.str();
}

// Velocity and acceleration of prescribed components at time t.
void apply_prescribed_motion(SceneBody& sb, double t, bool velocity, bool acceleration) {
  for (const auto& c : sb.conditions) {
    const std::uint8_t mask = c->prescribed_components();
    if (!mask || !c->prescribes_at(t)) continue;
    for (int k = 0; k < 3; ++k) {
      if (!(mask & (1u << k))) continue;
      const double v = c->prescribed_velocity(k, t), a = c->prescribed_acceleration(k, t);
      for (std::uint32_t i : c->points()) {
        if (velocity) sb.body.velocity[i][k] = v;
        if (acceleration) sb.body.acceleration[i][k] = a;
      }
    }
  }
}

// A body of more points than this is "large": it takes every thread for its kernel, one after
// another, where small ones run side by side (base/parallel_policy.hpp).
std::size_t parallel_points() {
  return parallel_thresholds().engine_points;
}

// Streaming per-point loops over more points than this run in parallel.
std::size_t parallel_loop_points() {
  return parallel_thresholds().engine_loop_points;
}

// Work increment of the external loads and reactions over a displacement increment dt*v:
// V/2 f_ext . du with f_ext = rho a - (b_total - b_ext) (for a free component that is b_ext;
// for a prescribed one it includes the reaction). Two of these per step make the trapezoidal
// rule in displacement.
double half_work_increment(const Body& b, double dt) {
  // Per-thread partial sums over a static schedule, added in thread order: the total does not
  // depend on which thread finished first (an OpenMP reduction's combining order may).
  // The buffer outlives the call: no allocation in a step once it holds the threads. The
  // threads of the region below write into the calling thread's buffer (the reference), not
  // into thread_locals of their own.
  static thread_local std::vector<double> partial_buffer;
  std::vector<double>& partial = partial_buffer;
  partial.assign(static_cast<std::size_t>(omp_get_max_threads()), 0.0);
  const std::size_t n = b.size();
#pragma omp parallel if (n > parallel_loop_points())
  {
    double w = 0;
#pragma omp for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      if (!b.books(i)) continue;  // a ghost: its owner books the work done on it
      const Vec3 f =
          b.density * b.acceleration[i] - (b.force_density[i] - b.external_force_density[i]);
      w += 0.5 * b.volume[i] * dt * f.dot(b.velocity[i]);
    }
    partial[static_cast<std::size_t>(omp_get_thread_num())] = w;
  }
  double total = 0;
  for (double w : partial) total += w;
  return total;
}

// The steps of size dt that cover `duration` (the last one shortened): refused, naming
// time.end, when they are more than a run plans (a count past 2^63 would wrap, and a run of 1e30
// s took one step of the whole duration).
long long planned_count(const TimeSettings& time, double duration, double dt, bool user_dt) {
  const double count = std::ceil(duration / dt - 1e-9);
  if (count <= static_cast<double>(TimeSettings::kMaxSteps)) return static_cast<long long>(count);
  std::ostringstream msg;
  msg << (time.end_where.empty() ? "time.end" : time.end_where) << " = " << time.end_time
      << " s: " << duration << " s to run at dt = " << dt << " s "
      << (user_dt ? "(time.dt)" : "(the stable step)") << " are " << count
      << " steps, more than the " << static_cast<double>(TimeSettings::kMaxSteps)
      << " a run may plan; expected an end time that a run reaches";
  if (user_dt) msg << ", or a larger time.dt";
  throw std::invalid_argument(msg.str());
}

// The fastest any point of the body is set to move by its conditions (initial and prescribed
// velocities) or its rigid motion, before the run starts.
double initial_speed(const SceneBody& sb) {
  double v = 0;
  for (const auto& c : sb.conditions) v = std::max(v, c->max_speed());
  if (sb.rigid) v = std::max(v, sb.rigid->max_speed(sb.body));
  return v;
}

// Where the fastest speed of initial_speed comes from: its condition's line, or the rigid
// body's motion.
std::string speed_source(const SceneBody& sb) {
  const double v = initial_speed(sb);
  for (const auto& c : sb.conditions)
    if (c->max_speed() == v && !c->where().empty()) return c->where();
  return "body '" + sb.body.name + "' (its rigid motion)";
}

// A condition that acts for no longer than one step ends before the first force evaluation
// after t = 0: a pulse p(t) = 4 p0 u (1 - u) is zero at t = 0, so it would put in no load, and a
// velocity would hold its points for no step. Refused rather than run as if it had acted.
void refuse_unsampled_durations(const Scene& scene, double dt) {
  for (const SceneBody& sb : scene.bodies)
    for (const auto& c : sb.conditions) {
      if (!(c->duration() <= dt)) continue;
      std::ostringstream msg;
      msg << c->duration_where() << " = " << c->duration() << " s on body '" << sb.body.name
          << "' is not longer than the time step dt = " << dt
          << " s: no step after t = 0 falls within it, so it would not act as written; expected "
             "a duration of more than one step (10 or more resolve a pulse's impulse to 1 %)";
      throw std::invalid_argument(msg.str());
    }
}

}  // namespace

std::vector<ContactPairRadius> contact_pair_radii(const Scene& scene) {
  std::vector<ContactPairRadius> pairs;
  if (!scene.contact.present) return pairs;
  const std::vector<ContactBody> bodies = contact_bodies(scene);
  for (std::size_t a = 0; a < bodies.size(); ++a)
    for (std::size_t b = a; b < bodies.size(); ++b)
      if (const std::optional<PairLaw> law = scene.contact.law(bodies, a, b))
        pairs.push_back({a, b, law->radius});
  return pairs;
}

StepChoice choose_time_step(const Scene& scene) {
  StepChoice c;
  c.estimate = std::numeric_limits<double>::infinity();
  // Contact stiffness adds to each point's bond stiffness bound (contact/contact_stiffness.hpp).
  const std::vector<double> contact_stiffness = contact_stiffness_bounds(scene);
  for (std::size_t index = 0; index < scene.bodies.size(); ++index) {
    const SceneBody& sb = scene.bodies[index];
    if (sb.rigid && sb.rigid->prescribed()) continue;  // its motion does not respond to forces
    const StableStep s = stable_step_with(sb.body, contact_stiffness[index]);
    if (s.dt < c.estimate) {
      c.estimate = s.dt;
      c.limiting_body = sb.body.name;
      c.limiting_point = s.point;
      c.limiting_position = sb.body.reference_position[s.point];
    }
  }
  if (!std::isfinite(c.estimate))
    throw std::invalid_argument(
        (scene.case_file.empty() ? std::string() : scene.case_file + ": bodies: ") +
        "no body has any interaction: the stable step is unbounded");
  // Contact tunnelling: two bodies closing at v_a + v_b cover that times dt per step.
  for (const ContactPairRadius& p : contact_pair_radii(scene)) {
    const double closing = initial_speed(scene.bodies[p.a]) + initial_speed(scene.bodies[p.b]);
    if (!(closing > 0)) continue;
    // The penalty stops a point of density rho closing at v within l_c only if
    // rho v^2 / 2 <= k l_c^2 / 2 (k: the point's contact stiffness bound, N/m^4). Faster, the
    // bodies pass through each other however small dt is: a sphere at 1e6 m/s crossed a plate
    // and the run "completed" with no damage, each body's own reach per step being small.
    double stoppable = std::numeric_limits<double>::infinity();
    std::string soft;
    for (const std::size_t side : {p.a, p.b}) {
      const SceneBody& sb = scene.bodies[side];
      if (sb.rigid || !(contact_stiffness[side] > 0) || !(sb.body.density > 0)) continue;
      const double v = p.radius * std::sqrt(contact_stiffness[side] / sb.body.density);
      if (v < stoppable) {
        stoppable = v;
        soft = sb.body.name;
      }
    }
    if (closing > stoppable && !scene.time.allow_unstable_dt) {
      std::ostringstream msg;
      // The speeds come from the case's initial or prescribed velocities: the faster body's.
      const SceneBody& fast = initial_speed(scene.bodies[p.a]) >= initial_speed(scene.bodies[p.b])
                                  ? scene.bodies[p.a]
                                  : scene.bodies[p.b];
      msg << speed_source(fast) << ": bodies " << scene.bodies[p.a].body.name << "/"
          << scene.bodies[p.b].body.name << " close at " << closing
          << " m/s, faster than their contact can stop within l_c = " << p.radius
          << " m (l_c sqrt(k / rho) = " << stoppable << " m/s for body '" << soft
          << "'): they would pass through each other; lower the speed, raise contact.stiffness "
          << "or contact.radius, or set time.allow_unstable_dt: true to run it anyway";
      throw std::invalid_argument(msg.str());
    }
    const double bound = kContactStepFraction * p.radius / closing;
    if (bound < c.speed_step) {
      c.speed_step = bound;
      c.closing_speed = closing;
      c.contact_radius = p.radius;
      c.speed_pair = scene.bodies[p.a].body.name + "/" + scene.bodies[p.b].body.name;
    }
  }
  if (scene.time.dt) {
    c.dt = *scene.time.dt;
    c.user_dt = true;
    if (c.dt > c.estimate && !scene.time.allow_unstable_dt) {
      std::ostringstream msg;
      msg << (scene.time.dt_where.empty() ? "time.dt" : scene.time.dt_where) << " = " << c.dt
          << " s exceeds the stable-step estimate " << c.estimate << " s (limited by body '"
          << c.limiting_body << "'); lower it, use dt: auto, or set "
          << "time.allow_unstable_dt: true to force it";
      throw std::invalid_argument(msg.str());
    }
    if (c.dt > c.speed_step && !scene.time.allow_unstable_dt) {
      std::ostringstream msg;
      msg << (scene.time.dt_where.empty() ? "time.dt" : scene.time.dt_where) << " = " << c.dt
          << " s exceeds the contact speed bound " << c.speed_step << " s (" << kContactStepFraction
          << " x l_c = " << c.contact_radius << " m over the "
          << "closing speed " << c.closing_speed << " m/s of bodies " << c.speed_pair
          << "): contact could tunnel; lower it, use dt: auto, or set "
          << "time.allow_unstable_dt: true to force it";
      throw std::invalid_argument(msg.str());
    }
  } else {
    c.dt = scene.time.safety * c.estimate;
    if (c.speed_step < c.dt) {
      c.dt = c.speed_step;
      c.speed_limited = true;
    }
  }
  c.safety = c.dt / c.estimate;
  return c;
}

std::string contact_speed_note(const StepChoice& c) {
  std::ostringstream s;
  s << "contact speed bound: " << kContactStepFraction << " x l_c " << c.contact_radius
    << " m / closing speed " << c.closing_speed << " m/s (bodies " << c.speed_pair
    << ") = " << c.speed_step << " s";
  if (c.speed_limited) s << "; dt lowered to it (below the safety x stable-step estimate)";
  return s.str();
}

Simulation::Simulation(Scene& scene) : Simulation(scene, nullptr) {}

Simulation::~Simulation() = default;

Simulation::Simulation(Scene& scene, std::unique_ptr<Distribution> distribution)
    : scene_(scene), distribution_(std::move(distribution)) {
  // A distributed run's step is the whole scene's (its parts' stiffness bounds are their own).
  step_choice_ = distribution_ ? distribution_->step_choice() : choose_time_step(scene_);
  if (scene_.time.steps >= 0) {
    planned_steps_ = scene_.time.steps;
  } else {
    // The last step is shortened so that the run ends exactly at time.end (it never goes past).
    planned_steps_ = std::max<long long>(
        1, planned_count(scene_.time, scene_.time.end_time, step_choice_.dt, step_choice_.user_dt));
    last_dt_ = scene_.time.end_time - static_cast<double>(planned_steps_ - 1) * step_choice_.dt;
  }
  refuse_unsampled_durations(scene_, step_choice_.dt);
  double max_speed = 0;
  for (SceneBody& sb : scene_.bodies) {
    for (const auto& c : sb.conditions) {
      c->initialise(sb.body);
      max_speed = std::max(max_speed, c->max_speed());
    }
    if (sb.rigid) {
      sb.rigid->initialise(sb.body);
      max_speed = std::max(max_speed, sb.rigid->max_speed(sb.body));
      continue;  // no lattice waves
    }
    if (distribution_) continue;  // the whole bodies' waves: below
    // omega_max dx bounds the fastest wave a lattice carries.
    const double k =
        *std::max_element(sb.body.stiffness_bound.begin(), sb.body.stiffness_bound.end());
    max_speed = std::max(max_speed, sb.spacing * std::sqrt(k / sb.body.density));
  }
  if (distribution_) max_speed = std::max(max_speed, distribution_->wave_speed());
  // No material point of a stable run moves at ten times the fastest wave or load speed. A
  // scene of rigid bodies at rest has neither (a block set down on a slope): no scale to judge
  // by, no limit.
  speed_limit_ = max_speed > 0 ? 10 * max_speed : std::numeric_limits<double>::infinity();
  // A part's bounds would see only its points (and none where the part of a body is empty).
  contact_stiffness_ =
      distribution_ ? distribution_->contact_stiffness() : contact_stiffness_bounds(scene_);
  for (const SceneBody& sb : scene_.bodies) {
    failed_.push_back(failed_bond_count(sb.body));
    initially_failed_.push_back(failed_.back());
  }
  if (distribution_) initially_failed_ = distribution_->initially_failed();
  contact_radius_.assign(scene_.bodies.size(), std::numeric_limits<double>::infinity());
  for (const ContactPairRadius& p : contact_pair_radii(scene_)) {
    contact_radius_[p.a] = std::min(contact_radius_[p.a], p.radius);
    contact_radius_[p.b] = std::min(contact_radius_[p.b], p.radius);
  }
  inverted_.assign(scene_.bodies.size(), 0);
  evaluated_.assign(scene_.bodies.size(), {});
  step_evaluated_.assign(scene_.bodies.size(), {});
  books_.evaluated.assign(scene_.bodies.size(), {});
  if (!distribution_)
    contact_ = make_contact_manager(scene_);
  else if (has_contact_work(scene_))
    contact_ghosts_ = std::make_unique<ContactGhosts>(scene_, *distribution_);
  taken_dt_ = step_choice_.dt;
  evaluate_forces(true);
  if (distribution_) reduce_books(true);
  const Energies e = energies();
  initial_total_ = e.kinetic + e.strain + e.contact;
  if (adaptive()) plan_next_step(current_step());
}

void Simulation::evaluate_forces(bool with_energy) {
  strain_energy_ = with_energy ? 0.0 : strain_energy_;
  const auto start = std::chrono::steady_clock::now();
  const std::size_t bodies = scene_.bodies.size();
  // The ghosts at the new positions (and their drift velocities, for the damage booking).
  if (distribution_) distribution_->exchange_state(scene_);
  std::vector<double>& dissipated = step_dissipated_;
  std::vector<double>& strain = step_strain_;
  dissipated.assign(bodies, 0.0);
  strain.assign(bodies, 0.0);
  auto add_loads_and_energy = [&](std::size_t index) {
    Body& b = scene_.bodies[index].body;
    const std::size_t n = b.size();
#pragma omp parallel for schedule(static) if (n > parallel_loop_points())
    for (std::size_t i = 0; i < n; ++i) b.force_density[i] += b.external_force_density[i];
    if (with_energy) strain[index] = strain_energy(b);
  };
  auto own_forces = [&](std::size_t index) {
    SceneBody& sb = scene_.bodies[index];
    Body& b = sb.body;
    std::fill(b.external_force_density.begin(), b.external_force_density.end(), Vec3::Zero());
    for (const auto& c : sb.conditions) c->add_external_force(b, time_);
    if (sb.rigid) {
      b.force_density = b.external_force_density;  // no internal forces
      sb.rigid->clear_couple();
      return;
    }
    // velocity holds the drift velocity of the step (kick-drift-kick): the lost energy is
    // booked at the step's midpoint, where the integrator's force switch effectively happens.
    // Each bond, triangle and tetrahedron once (the per-point reference kernel in reference/ is
    // what it is tested against); a bond-only body fails its bonds in the same pass.
    FailureUpdate failure;
    SymmetricKernelStats stats;
    if (sb.far_field) {
      failure = fail_overstretched_bonds(b, 0.5 * step_size(step_));
      stats = compute_internal_force_far_field(b, *sb.far_field, with_energy);
    } else {
      stats =
          fail_bonds_and_compute_internal_force(b, with_energy, 0.5 * step_size(step_), failure);
    }
    dissipated[index] = failure.dissipated;
    failed_[index] += failure.failed;
    if (with_energy) inverted_[index] = stats.inverted_tetrahedra + stats.inverted_triangles;
    step_evaluated_[index] = {stats.bonds, stats.triangles, stats.tetrahedra};
    Evaluated& total = evaluated_[index];
    total.bonds += stats.bonds;
    total.triangles += stats.triangles;
    total.tetrahedra += stats.tetrahedra;
    // A body whose force work is shared over ranks has this rank's part only: it is completed
    // after the sum over ranks below.
    if (!shares_force_work(b)) add_loads_and_energy(index);
  };
  // Small bodies side by side, one per thread (the parallel regions of their kernels, nested,
  // run on that thread alone); large ones one after another, each with every thread. Rigid
  // bodies only copy their loads and do not count: one small deformable body beside a rigid
  // indenter gets every thread for its kernel (bench/lammps_compare.sh: it ran on one).
  std::vector<std::size_t>& small = small_bodies_;
  std::vector<std::size_t>& large = large_bodies_;
  small.clear();
  large.clear();
  for (std::size_t k = 0; k < bodies; ++k) {
    if (scene_.bodies[k].rigid)
      own_forces(k);
    else
      (scene_.bodies[k].body.size() < parallel_points() ? small : large).push_back(k);
  }
  // Static, one body at a time round the team: body k runs on the same thread every step. The
  // kernels keep their scratch per calling thread (thread_local workspaces), so with a dynamic
  // schedule a thread could meet a larger body for the first time after warm-up and allocate in
  // a step (the frictional-contact allocation test failed 1 run in 3 that way).
#pragma omp parallel for schedule(static, 1) if (small.size() > 1)
  for (std::size_t k = 0; k < small.size(); ++k) own_forces(small[k]);
  for (std::size_t k : large) own_forces(k);
  if (distribution_) {
    distribution_->sum_forces(scene_, with_energy);
    for (std::size_t k = 0; k < bodies; ++k)
      if (!scene_.bodies[k].rigid) add_loads_and_energy(k);  // a rigid body has its loads
  } else if (shared_force_values(scene_, with_energy) > 0) {
    sum_shared_forces(scene_, with_energy, inverted_, sharing_);
    for (std::size_t k = 0; k < bodies; ++k)
      if (shares_force_work(scene_.bodies[k].body)) add_loads_and_energy(k);
  }
  // In body order: the same sums on every thread count.
  for (std::size_t k = 0; k < bodies; ++k) {
    dissipated_ += dissipated[k];
    if (with_energy) strain_energy_ += strain[k];
  }
  if (with_energy && !distribution_) {  // distributed: after the sum over ranks (reduce_books)
    max_inverted_ = std::max(max_inverted_, inverted());
    for (std::size_t k = 0; k < bodies && first_inversion_.step < 0; ++k)
      if (inverted_[k] > 0)
        first_inversion_ = {step_, time_, scene_.bodies[k].body.name, inverted_[k]};
  }
  body_force_seconds_ +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // Contact couples the bodies: it runs once all of them are at the new positions.
  // The springs advance over the step just taken; the first evaluation follows none.
  const double contact_dt = step_ > 0 ? (adaptive() ? taken_dt_ : step_choice_.dt) : 0.0;
  if (contact_) {
    contact_point_sets(scene_, point_sets_);
    contact_->rebind(point_sets_);
    contact_->add_forces(contact_dt);
  } else if (contact_ghosts_) {
    contact_ghosts_->add_forces(contact_dt);
  }
  for (SceneBody& sb : scene_.bodies) {
    Body& b = sb.body;
    if (sb.rigid) {
      sb.rigid->set_accelerations(b, time_);
      continue;
    }
    const double inv_rho = 1 / b.density;
    const std::size_t n = b.size();
#pragma omp parallel for schedule(static) if (n > parallel_loop_points())
    for (std::size_t i = 0; i < n; ++i) b.acceleration[i] = inv_rho * b.force_density[i];
    apply_prescribed_motion(sb, time_, false, true);
  }
}

double Simulation::step_size(long long index) const {
  if (adaptive()) return index <= step_ ? taken_dt_ : next_dt_;
  return index == planned_steps_ && last_dt_ > 0 ? last_dt_ : step_choice_.dt;
}

double Simulation::next_time() const {
  if (adaptive())
    return scene_.time.steps < 0 && step_ + 1 == planned_steps_ ? scene_.time.end_time
                                                                : time_ + next_dt_;
  return step_ + 1 == planned_steps_ && last_dt_ > 0
             ? scene_.time.end_time
             : origin_time_ + static_cast<double>(step_ + 1 - origin_step_) * step_choice_.dt;
}

void Simulation::plan_next_step(const CurrentStep& now) {
  current_stable_ = now.dt;
  // safety x the current stable step, and the kinematic limit, never above dt (a bound within
  // rounding of dt keeps dt: at the reference state the current-state bound is the reference
  // one to rounding).
  const double bound = std::min(scene_.time.safety * now.dt, now.kinematic);
  next_choice_ = bound < step_choice_.dt * (1 - 1e-12) ? bound : step_choice_.dt;
  const double floor = scene_.time.smallest_step > 0 ? scene_.time.smallest_step
                                                     : kSmallestStepFraction * step_choice_.dt;
  // (From the second step on: the run has begun, its output with it.)
  if (next_choice_ < floor && step_ > 0) report_step_collapse(now, floor);
  clip_next_step();
}

void Simulation::report_step_collapse(const CurrentStep& now, double floor) const {
  const Body& b = scene_.bodies[now.body].body;
  std::ostringstream msg;
  msg << "step collapse at step " << step_ << ", t = " << time_ << " s: the adaptive step fell to "
      << next_choice_ << " s, below time.smallest_step = " << floor << " s";
  if (!(scene_.time.smallest_step > 0)) msg << " (the default, 1e-12 x dt)";
  msg << "; body '" << b.name << "' has a stable step of " << now.dt << " s at point " << now.point
      << " (reference " << format_position(b.reference_position[now.point], b.dimension)
      << "), the kinematic limit is " << now.kinematic
      << " s: a bond or set is closing and the step follows it down, so the run would not reach "
         "its end (docs/STABILITY.md: with m = 0 a set can close to the rounding of its volume; "
         "m = -1/2 stops it at a finite ratio)";
  throw InstabilityError(msg.str());
}

void Simulation::clip_next_step() {
  next_dt_ = next_choice_;
  if (scene_.time.steps >= 0) {
    planned_steps_ = scene_.time.steps;
    return;
  }
  // A run to time.end lands on it: the step that reaches it is the remainder, and a remainder
  // between one and two steps is split in halves (no sliver of a last step).
  const double left = scene_.time.end_time - time_;
  if (!(left > 0)) {
    planned_steps_ = step_;
  } else if (left <= next_dt_ * (1 + 1e-9)) {
    next_dt_ = left;
    planned_steps_ = step_ + 1;
  } else if (left < 2 * next_dt_) {
    next_dt_ = 0.5 * left;
    planned_steps_ = step_ + 2;
  } else {
    // A plan for the progress line: an adaptive step may fall far below dt, so the count
    // saturates instead of overflowing (the run ends at time.end, not at this count).
    const double count = std::ceil(left / next_dt_ - 1e-9);
    planned_steps_ = step_ + static_cast<long long>(std::min(count, 9e18 - double(step_)));
  }
}

void Simulation::report_instability(std::size_t index, double worst, std::size_t worst_point,
                                    const Vec3& reference, bool finite, double dt) {
  const Body& b = scene_.bodies[index].body;
  std::ostringstream msg;
  msg << "instability at step " << step_ << ", t = " << time_ << " s: body '" << b.name
      << "', point " << worst_point << " at reference " << format_position(reference, b.dimension)
      << " ";
  if (!finite)
    msg << "has a non-finite velocity or displacement";
  else
    msg << "moves at " << std::sqrt(worst) << " m/s, over the guard's limit of " << speed_limit_
        << " m/s (ten times the fastest wave or load speed)";
  msg << "; dt = " << dt << " s is " << step_choice_.safety << " x the stable-step estimate";
  throw InstabilityError(msg.str());
}

void Simulation::advance(bool with_energy) {
  const double dt = step_size(step_ + 1);
  // Kick to t + dt/2, prescribed velocities at the midpoint (exact for a linear ramp), drift.
  for (SceneBody& sb : scene_.bodies) {
    Body& b = sb.body;
    if (sb.rigid) {
      sb.rigid->first_half(b, time_, dt);
      external_work_ += half_work_increment(b, dt);
      continue;
    }
    const std::size_t n = b.size();
#pragma omp parallel for schedule(static) if (n > parallel_loop_points())
    for (std::size_t i = 0; i < n; ++i) b.velocity[i] += 0.5 * dt * b.acceleration[i];
    apply_prescribed_motion(sb, time_ + 0.5 * dt, true, false);
    external_work_ += half_work_increment(b, dt);
#pragma omp parallel for schedule(static) if (n > parallel_loop_points())
    for (std::size_t i = 0; i < n; ++i) b.displacement[i] += dt * b.velocity[i];
  }
  time_ = next_time();
  if (adaptive() && next_choice_ < step_choice_.dt) {
    ++reduced_steps_;
    smallest_step_ = std::min(smallest_step_, next_choice_);
  }
  ++step_;
  taken_dt_ = dt;
  evaluate_forces(with_energy);
  if (!adaptive())
    check_stable_step();  // before the kick: a step past the current stable step is not taken
  for (std::size_t index = 0; index < scene_.bodies.size(); ++index) {
    SceneBody& sb = scene_.bodies[index];
    Body& b = sb.body;
    external_work_ += half_work_increment(b, dt);
    // A rigid body's point velocities follow from its own kick; the loop below only checks them.
    if (sb.rigid) sb.rigid->second_half(b, time_, dt);
    const bool kick = !sb.rigid;
    const std::size_t n = b.size();
    double worst = 0;
    std::size_t worst_point = 0;
    bool finite = true;
#pragma omp parallel if (n > parallel_loop_points())
    {
      double my_worst = 0;
      std::size_t my_point = 0;
      bool my_finite = true;
#pragma omp for schedule(static) nowait
      for (std::size_t i = 0; i < n; ++i) {
        if (kick) b.velocity[i] += 0.5 * dt * b.acceleration[i];
        // A ghost's velocity is its owner's, sent with the next step's state: the owner judges.
        if (!b.books(i)) continue;
        const double s2 = b.velocity[i].squaredNorm();
        if (!std::isfinite(s2) || !b.displacement[i].allFinite()) {
          my_finite = false;
          my_point = i;
          my_worst = std::numeric_limits<double>::infinity();
        } else if (s2 > my_worst && my_finite) {
          my_worst = s2;
          my_point = i;
        }
      }
#pragma omp critical
      {
        if ((!my_finite && finite) ||
            (my_finite == finite &&
             (my_worst > worst || (my_worst == worst && my_point < worst_point)))) {
          worst = my_worst;
          worst_point = my_point;
        }
        finite = finite && my_finite;
      }
    }
    apply_prescribed_motion(sb, time_, true, false);
    Vec3 reference = n > 0 ? b.reference_position[worst_point] : Vec3::Zero();
    if (distribution_) {
      // Every rank's fastest point of this body, the same choice on every rank; the point named
      // by its index in the whole body.
      const double key = n == 0 ? -1 : finite ? worst : std::numeric_limits<double>::infinity();
      const Distribution::Choice c = distribution_->choose(scene_, key, index, worst_point);
      finite = !(c.key == std::numeric_limits<double>::infinity());
      worst = std::max(c.key, 0.0);
      worst_point = c.point;
      reference = c.reference;
    }
    if (!finite || std::sqrt(worst) > speed_limit_)
      report_instability(index, worst, worst_point, reference, finite, dt);
    // Tunnelling: the fastest point covers |v| dt per step (the end-of-step speed, which the
    // next drift uses, found in the loop above at no extra cost).
    const double reach = std::sqrt(worst) * dt;
    if (reach > kTunnellingFraction * contact_radius_[index]) {
      std::ostringstream msg;
      msg << "contact tunnelling at step " << step_ << ", t = " << time_ << " s: body '" << b.name
          << "', point " << worst_point << " at reference "
          << format_position(b.reference_position[worst_point], b.dimension) << " moves " << reach
          << " m per step (" << std::sqrt(worst) << " m/s), more than " << kTunnellingFraction
          << " x its smallest contact radius l_c = " << contact_radius_[index]
          << " m; lower dt (the contact speed bound at the start is " << step_choice_.speed_step
          << " s)";
      throw TunnellingError(msg.str());
    }
  }
  if (adaptive()) {
    // After the kick (the kinematic limit reads the velocities at the end of the step): the
    // step just taken against the stable step where it ended (a stiffening faster than the
    // safety margin within one step stops the run, as the fixed step's guard does), then the
    // next step from it. The kick above completed this step with its own dt / 2, and the next
    // step's first kick uses the next dt / 2: each step is velocity Verlet with one dt.
    const CurrentStep now = current_step();
    if (dt > now.dt && !scene_.time.allow_unstable_dt) {
      const Body& b = scene_.bodies[now.body].body;
      std::ostringstream msg;
      msg << "instability at step " << step_ << ", t = " << time_ << " s: body '" << b.name
          << "' now has a stable step of " << now.dt << " s at point " << now.point
          << " (reference " << format_position(b.reference_position[now.point], b.dimension)
          << "), below the adaptive step just taken, " << dt << " s (time.safety "
          << scene_.time.safety << " x the stable step where it began): the stable step fell "
          << "by more than the safety margin within one step; rerun with a lower time.safety";
      throw InstabilityError(msg.str());
    }
    plan_next_step(now);
  }
  if (with_energy) {
    kick_work_ = 0;
    for (const SceneBody& sb : scene_.bodies) kick_work_ += half_work_increment(sb.body, dt);
  }
  if (distribution_) reduce_books(with_energy);
  if (with_energy) check_energy();
}

void Simulation::reduce_books(bool with_energy) {
  const std::size_t bodies = scene_.bodies.size();
  std::vector<double>& v = book_values_;
  const ContactManager* manager = contact_ghosts_ ? &contact_ghosts_->manager() : nullptr;
  v.assign({external_work_, dissipated_, strain_energy_, kinetic_energy(),
            manager ? manager->energy() : 0.0, manager ? manager->damping_dissipated() : 0.0,
            manager ? manager->friction_dissipated() : 0.0,
            manager ? static_cast<double>(manager->statistics().contact_ends) : 0.0, kick_work_});
  const std::size_t failed_at = v.size(), inverted_at = failed_at + bodies;
  for (std::size_t k = 0; k < bodies; ++k) v.push_back(static_cast<double>(failed_[k]));
  for (std::size_t k = 0; k < bodies; ++k) v.push_back(static_cast<double>(inverted_[k]));
  // This step's counts (below 2^53 each: summed exactly), added to the books below.
  const std::size_t evaluated_at = v.size();
  for (std::size_t k = 0; k < bodies; ++k) {
    v.push_back(static_cast<double>(step_evaluated_[k].bonds));
    v.push_back(static_cast<double>(step_evaluated_[k].triangles));
    v.push_back(static_cast<double>(step_evaluated_[k].tetrahedra));
    step_evaluated_[k] = {};
  }
  // The largest damage of this rank's booked points: a max over ranks, not a sum.
  double damage = 0;
  for (const SceneBody& sb : scene_.bodies)
    if (sb.body.damage_enabled) damage = std::max(damage, max_point_damage(sb.body));
  const std::size_t summed = v.size();
  v.push_back(damage);
  v.push_back(contact_ghosts_ ? static_cast<double>(contact_ghosts_->ghosts()) : 0.0);
  distribution_->sum_and_max(v, summed);  // the counts are integers below 2^53: summed exactly
  books_.max_damage = v[summed];
  books_.contact_ghosts_peak =
      std::max(books_.contact_ghosts_peak, static_cast<std::uint64_t>(v[summed + 1]));
  books_.external_work = v[0];
  books_.dissipated = v[1];
  books_.kinetic = v[3];
  books_.contact = v[4];
  books_.contact_damping = v[5];
  books_.contact_friction = v[6];
  books_.kick_work = v[8];
  books_.contact_pairs = static_cast<std::uint64_t>(v[7]) / 2;
  books_.contact_pairs_peak = std::max(books_.contact_pairs_peak, books_.contact_pairs);
  books_.failed.resize(bodies);
  for (std::size_t k = 0; k < bodies; ++k)
    books_.failed[k] = static_cast<std::size_t>(v[failed_at + k]);
  for (std::size_t k = 0; k < bodies; ++k) {
    Evaluated& e = books_.evaluated[k];
    e.bonds += static_cast<std::uint64_t>(v[evaluated_at + 3 * k]);
    e.triangles += static_cast<std::uint64_t>(v[evaluated_at + 3 * k + 1]);
    e.tetrahedra += static_cast<std::uint64_t>(v[evaluated_at + 3 * k + 2]);
  }
  if (!with_energy) return;
  books_.strain = v[2];
  books_.inverted.resize(bodies);
  for (std::size_t k = 0; k < bodies; ++k)
    books_.inverted[k] = static_cast<std::uint64_t>(v[inverted_at + k]);
  max_inverted_ = std::max(max_inverted_, inverted());
  for (std::size_t k = 0; k < bodies && first_inversion_.step < 0; ++k)
    if (books_.inverted[k] > 0)
      first_inversion_ = {step_, time_, scene_.bodies[k].body.name, books_.inverted[k]};
}

bool stiffens_in_compression(const Body& b) {
  if (b.model == &state_based_kernels()) return b.state_based.m <= 0;
  // Either CKPD force form: the bond's and the sets' stiffening are the same in both.
  return (b.model == &ckpd_seth_hill_kernels() ||
          b.model == &ckpd_seth_hill_conservative_kernels()) &&
         b.strain_measure <= 0;
}

namespace {

double measure_of(const Body& b) {
  return b.model == &state_based_kernels() ? b.state_based.m : b.strain_measure;
}

// The adaptive step's kinematic limit: a step in which no bond or set of a body with measure m
// shrinks by more than a fraction f of itself. A set's share of the stiffness bound grows as its
// ratio's curvature r^(4m - 2) (the leading term as r -> 0, THEORY.md section 6), so a fall
// from r to (1 - f) r raises it by (1 - f)^(4m - 2). At time.safety s = 0.8, f = 1 -
// 0.8^(1 / (2 - 4m)) (0.106 for m = 0, 0.054 for m = -1/2) keeps that to 1 / s = 1.25 per step,
// half (in log) of the 1 / s^2 = 1.56 that a step at s x the stable step can absorb before the
// guard trips; f scales with s (halving time.safety halves every limit of the step).
double shrink_fraction(double m, double safety) {
  return safety / 0.8 * (1 - std::pow(0.8, 1 / (2 - 4 * m)));
}

// The stable step of a body at its current displacement (see check_stable_step).
// shrink (optional): the least time in which a bond or set of the body would collapse at the
// current velocities (current_stiffness.hpp).
StableStep stable_step_now(const Body& b, double extra_stiffness, double* shrink = nullptr) {
  std::vector<double> k, t;
  if (b.model == &state_based_kernels()) {
    state_based_stiffness_bound(b, k);
    if (shrink) bond_shrink_time(b, t);
  } else {
    // bonds, triangles and tetrahedra where they are now
    ckpd_current_stiffness_bound(b, k, shrink ? &t : nullptr);
  }
  if (shrink)
    *shrink =
        t.empty() ? std::numeric_limits<double>::infinity() : *std::min_element(t.begin(), t.end());
  StableStep s;
  for (std::size_t i = 0; i < b.size(); ++i) {
    const double total = k[i] + extra_stiffness;
    if (!(total > 0)) continue;
    const double dt = 2.0 * std::sqrt(b.density / total);
    if (dt < s.dt || !std::isfinite(dt)) s = {dt, i};
  }
  return s;
}

}  // namespace

Simulation::CurrentStep Simulation::current_step() {
  const auto start = std::chrono::steady_clock::now();
  CurrentStep best;
  for (std::size_t index = 0; index < scene_.bodies.size(); ++index) {
    const SceneBody& sb = scene_.bodies[index];
    if (sb.rigid || !stiffens_in_compression(sb.body)) continue;
    double shrink = std::numeric_limits<double>::infinity();
    const StableStep now = stable_step_now(sb.body, contact_stiffness_[index], &shrink);
    if (now.dt < best.dt) {
      best.dt = now.dt;
      best.body = index;
      best.point = now.point;
    }
    best.kinematic =
        std::min(best.kinematic, shrink_fraction(measure_of(sb.body), scene_.time.safety) * shrink);
  }
  stable_step_seconds_ +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return best;
}

void Simulation::check_stable_step() {
  // A guard, not a re-estimate that lowers dt: the step is fixed for the run (the output
  // schedule, time.end's last step and a restart's step/time identity rest on it). A body whose
  // measure stiffens in compression has its stable step estimated at the current state after
  // every force evaluation; when dt exceeds it the run stops as unstable, naming the safety
  // factor that would have held, before the blow-up that the reference estimate lets through.
  if (scene_.time.allow_unstable_dt) return;
  for (std::size_t index = 0; index < scene_.bodies.size(); ++index) {
    const SceneBody& sb = scene_.bodies[index];
    if (sb.rigid || !stiffens_in_compression(sb.body)) continue;
    const auto start = std::chrono::steady_clock::now();
    const StableStep now = stable_step_now(sb.body, contact_stiffness_[index]);
    stable_step_seconds_ +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double dt = step_choice_.dt;
    if (dt <= now.dt) continue;
    const Body& b = sb.body;
    const double m = b.model == &state_based_kernels() ? b.state_based.m : b.strain_measure;
    std::ostringstream msg;
    msg << "instability at step " << step_ << ", t = " << time_ << " s: body '" << b.name
        << "' (strain measure m = " << m << ", which stiffens in compression) now has a stable "
        << "step of " << now.dt << " s at point " << now.point << " (reference "
        << format_position(b.reference_position[now.point], b.dimension) << "), below dt = " << dt
        << " s (" << step_choice_.safety << " x the reference-state estimate "
        << step_choice_.estimate
        << " s); rerun with time.safety <= " << step_choice_.safety * now.dt / dt
        << " or time.dt <= " << now.dt << " s";
    throw InstabilityError(msg.str());
  }
}

void Simulation::check_energy() const {
  const Energies e = energies();
  const double now = e.kinetic + e.strain + e.contact;
  // The energy put in: at the start, plus the loads' work to the end of the step's last kick.
  const double kick_work = distribution_ ? books_.kick_work : kick_work_;
  const double supplied = initial_total_ + std::abs(e.external_work) + std::abs(kick_work);
  if (now > 0 && now > 10 * supplied) {
    // Where: the point with the largest kinetic plus strain energy.
    const Body* where_body = nullptr;
    std::size_t where_point = 0;
    double largest = -1;
    std::size_t where_index = 0;
    for (std::size_t k = 0; k < scene_.bodies.size(); ++k) {
      const Body& b = scene_.bodies[k].body;
      for (std::size_t i = 0; i < b.size(); ++i) {
        if (!b.books(i)) continue;  // a ghost's strain energy density is a partial
        const double density =
            0.5 * b.density * b.velocity[i].squaredNorm() + b.strain_energy_density[i];
        if (density > largest) {
          largest = density;
          where_body = &b;
          where_index = k;
          where_point = i;
        }
      }
    }
    Vec3 reference = where_body ? where_body->reference_position[where_point] : Vec3::Zero();
    if (distribution_) {
      const Distribution::Choice c =
          distribution_->choose(scene_, largest, where_index, where_point);
      where_body = &scene_.bodies[c.body].body;
      where_point = c.point;
      reference = c.reference;
    }
    std::ostringstream msg;
    msg << "instability at step " << step_ << ", t = " << time_
        << " s: kinetic + strain + contact energy " << now
        << " J is more than ten times the energy put in (" << supplied
        << " J), most of it at body '" << where_body->name << "', point " << where_point
        << " at reference " << format_position(reference, where_body->dimension)
        << "; dt = " << step_choice_.dt << " s is " << step_choice_.safety
        << " x the stable-step estimate";
    throw InstabilityError(msg.str());
  }
}

Simulation::Counters Simulation::counters() const {
  const Energies e = energies();  // a distributed run's: the sums over ranks
  Counters c{time_,    step_,          e.external_work,  e.dissipated,
             e.strain, initial_total_, initially_failed_};
  c.next_dt = next_choice_;
  c.smallest_step = smallest_step_;
  c.reduced_steps = reduced_steps_;
  return c;
}

void Simulation::restore(const Counters& c) {
  time_ = c.time;
  step_ = c.step;
  if (adaptive()) {
    // The next step as the run chose it; clipped again, so that a later time.end continues.
    next_choice_ = c.next_dt;
    smallest_step_ = c.smallest_step;
    reduced_steps_ = c.reduced_steps;
    clip_next_step();
    external_work_ = c.external_work;
    dissipated_ = c.dissipated;
    strain_energy_ = c.strain_energy;
    initial_total_ = c.initial_total;
    initially_failed_ = c.initially_failed;
    return;
  }
  // Steps after a restart count from the checkpoint when its time ended a shortened last step
  // (a later time.end); otherwise from 0 as in the run it continues (bit for bit).
  const bool on_grid = c.time == static_cast<double>(c.step) * step_choice_.dt;
  origin_time_ = on_grid ? 0.0 : c.time;
  origin_step_ = on_grid ? 0 : c.step;
  if (scene_.time.steps < 0) {
    const double left = scene_.time.end_time - c.time;
    const auto more = std::max<long long>(
        0, planned_count(scene_.time, left, step_choice_.dt, step_choice_.user_dt));
    planned_steps_ = c.step + more;
    last_dt_ = more > 0 ? left - static_cast<double>(more - 1) * step_choice_.dt : 0;
  }
  external_work_ = c.external_work;
  dissipated_ = c.dissipated;
  strain_energy_ = c.strain_energy;
  initial_total_ = c.initial_total;
  initially_failed_ = c.initially_failed;
  if (contact_ghosts_) contact_ghosts_->invalidate();  // chosen at the state before the restart
  if (distribution_) {
    // The sums over ranks start from rank 0's share; the bodies' flags are restored already.
    if (distribution_->rank() != 0) external_work_ = dissipated_ = strain_energy_ = 0;
    for (std::size_t k = 0; k < scene_.bodies.size(); ++k)
      failed_[k] = failed_bond_count(scene_.bodies[k].body);
    reduce_books(false);
    books_.strain = c.strain_energy;
  }
}

void Simulation::refresh_strain_energy() {
  // A distributed run's ghosts were moved by the step with partial forces: their owners' state.
  if (distribution_) distribution_->exchange_state(scene_);
  const std::size_t bodies = scene_.bodies.size();
  std::vector<double>& strain = step_strain_;
  strain.assign(bodies, 0.0);
  std::vector<std::vector<Vec3>> kept(bodies);
  for (std::size_t k = 0; k < bodies; ++k) {
    SceneBody& sb = scene_.bodies[k];
    if (sb.rigid) continue;
    Body& b = sb.body;
    // The kernel overwrites the force density (internal plus the external loads added after
    // it); the step's forces must stay the ones the next kick uses.
    kept[k] = b.force_density;
    const SymmetricKernelStats stats =
        sb.far_field ? compute_internal_force_far_field(b, *sb.far_field, true)
                     : compute_internal_force_symmetric(b, true);
    inverted_[k] = stats.inverted_tetrahedra + stats.inverted_triangles;
  }
  // Bodies whose force work is shared over ranks: the energies and counts summed over ranks.
  if (distribution_)
    distribution_->sum_forces(scene_, true);
  else
    sum_shared_forces(scene_, true, inverted_, sharing_);
  for (std::size_t k = 0; k < bodies; ++k) {
    SceneBody& sb = scene_.bodies[k];
    if (sb.rigid) continue;
    sb.body.force_density.swap(kept[k]);
    strain[k] = strain_energy(sb.body);
  }
  strain_energy_ = 0;
  for (std::size_t k = 0; k < bodies; ++k) strain_energy_ += strain[k];  // body order
  if (distribution_)
    reduce_books(true);
  else
    max_inverted_ = std::max(max_inverted_, inverted());
}

double Simulation::kinetic_energy() const {
  double kinetic = 0;
  for (const SceneBody& sb : scene_.bodies) {
    const Body& b = sb.body;
    for (std::size_t i = 0; i < b.size(); ++i)
      if (b.books(i)) kinetic += 0.5 * b.density * b.volume[i] * b.velocity[i].squaredNorm();
    // A DEM sphere's spin is not in its one point's velocity.
    if (sb.rigid && b.size() > 0 && b.books(0)) kinetic += sb.rigid->spin_energy_beyond_points();
  }
  return kinetic;
}

const ContactManager* Simulation::contact() const {
  return contact_ghosts_ ? &contact_ghosts_->manager() : contact_.get();
}

std::uint64_t Simulation::contact_ghost_selections() const {
  return contact_ghosts_ ? contact_ghosts_->selections() : 0;
}

void Simulation::restore_contact(const ContactManager::HistoryState& state) {
  if (!contact_ghosts_) {
    contact_->restore_history(state);
    return;
  }
  // The ranks' dissipation books start from rank 0's share, as the other books do (restore).
  ContactManager::HistoryState mine = state;
  if (distribution_->rank() != 0) mine.damping_dissipated = mine.friction_dissipated = 0;
  contact_ghosts_->restore_history(mine);
  books_.contact_damping = state.damping_dissipated;
  books_.contact_friction = state.friction_dissipated;
}

ContactManager::HistoryState Simulation::contact_history() const {
  const ContactManager* manager = contact();
  if (!manager) return {};
  ContactManager::HistoryState h = manager->history();
  if (distribution_) {
    h.damping_dissipated = books_.contact_damping;
    h.friction_dissipated = books_.contact_friction;
  }
  return h;
}

Energies Simulation::energies() const {
  Energies e;
  e.kinetic = distribution_ ? books_.kinetic : kinetic_energy();
  e.strain = distribution_ ? books_.strain : strain_energy_;
  const ContactManager* manager = contact();
  e.contact = distribution_ ? books_.contact : manager ? manager->energy() : 0.0;
  e.external_work = distribution_ ? books_.external_work : external_work_;
  e.dissipated = distribution_ ? books_.dissipated : dissipated_;
  if (distribution_) {
    e.contact_damping = books_.contact_damping;
    e.contact_friction = books_.contact_friction;
  } else if (manager) {
    e.contact_damping = manager->damping_dissipated();
    e.contact_friction = manager->friction_dissipated();
  }
  e.balance_error = e.kinetic + e.strain + e.contact + e.dissipated + e.contact_damping +
                    e.contact_friction - e.external_work - initial_total_;
  return e;
}

std::size_t Simulation::broken_bonds(std::size_t body) const {
  if (distribution_) return books_.failed[body] - initially_failed_[body];
  return failed_bond_count(scene_.bodies[body].body) - initially_failed_[body];
}

std::size_t Simulation::broken_bonds() const {
  std::size_t total = 0;
  for (std::size_t b = 0; b < scene_.bodies.size(); ++b) total += broken_bonds(b);
  return total;
}

std::uint64_t Simulation::inverted() const {
  std::uint64_t total = 0;
  for (std::uint64_t n : distribution_ ? books_.inverted : inverted_) total += n;
  return total;
}

bool Simulation::has_far_field() const {
  for (const SceneBody& sb : scene_.bodies)
    if (sb.far_field) return true;
  return false;
}

double Simulation::exact_fraction() const {
  std::size_t exact = 0, points = 0;
  for (const SceneBody& sb : scene_.bodies) {
    if (!sb.far_field) continue;
    exact += sb.far_field->exact_count;
    points += sb.body.size();
  }
  return points > 0 ? static_cast<double>(exact) / static_cast<double>(points) : 1.0;
}

double Simulation::max_damage() const {
  if (distribution_) return books_.max_damage;
  double d = 0;
  for (const SceneBody& sb : scene_.bodies)
    if (sb.body.damage_enabled) d = std::max(d, max_point_damage(sb.body));
  return d;
}

void Simulation::gather_whole() {
  if (!distribution_) return;
  if (!whole_) throw std::logic_error("Simulation::gather_whole: no whole scene to gather into");
  distribution_->gather(scene_, *whole_);
}

}  // namespace ckpd
