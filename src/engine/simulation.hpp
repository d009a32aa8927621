#pragma once
// Velocity-Verlet time integration of all bodies (THEORY.md section 6), the stable-step
// choice, energy bookkeeping and the instability guard.
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "contact/contact_manager.hpp"
#include "src/engine/force_sharing.hpp"
#include "src/engine/scene.hpp"

namespace ckpd {

// The run went unstable; the message says where and when.
class InstabilityError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The time step and how it was chosen.
struct StepChoice {
  double estimate = 0;  // the stable-step estimate (min over bodies and points)
  double safety = 0;    // dt / estimate
  double dt = 0;
  bool user_dt = false;
  std::string limiting_body;
  std::size_t limiting_point = 0;
  Vec3 limiting_position = Vec3::Zero();
  // Contact tunnelling bound (kContactStepFraction l_c / closing speed) from the fastest pair
  // of bodies in contact: infinite without contact or motion.
  double speed_step = std::numeric_limits<double>::infinity();
  double closing_speed = 0;    // m/s: the two bodies' largest initial speeds added
  double contact_radius = 0;   // m: that pair's l_c
  std::string speed_pair;      // "a/b"
  bool speed_limited = false;  // dt = speed_step (below safety x estimate)
};

// Per step, a point may close at most this fraction of the contact radius l_c on a partner at
// the start of a run. The contact force grows linearly over the shell l_c - r, and the
// integrator samples it once per step: at l_c/4 per step a point meeting another head-on is
// pushed in at least four steps before the two could coincide (r = 0, where the force's
// direction is lost), and no step can carry a point across the 2 l_c wide shell around a
// partner without it being seen there. Larger fractions were the tunnelling seen in the stress
// table's fast impacts (docs/STABILITY.md).
inline constexpr double kContactStepFraction = 0.25;
// During the run, a point of a body in contact that moves more than this fraction of its
// smallest l_c in one step stops the run (TunnellingError): contact can no longer be trusted.
inline constexpr double kTunnellingFraction = 0.5;

// A point of a body in contact moved too far in one step (kTunnellingFraction).
class TunnellingError : public InstabilityError {
 public:
  using InstabilityError::InstabilityError;
};

// Chooses dt for the scene: safety x estimate, or the case's dt (refused when it exceeds the
// estimate unless allow_unstable_dt). The contact speed bound (StepChoice::speed_step) is
// handled the same way: an automatic dt is lowered to it (speed_limited, reported), a case's dt
// above it is refused unless allow_unstable_dt. Throws std::invalid_argument when refused.
StepChoice choose_time_step(const Scene& scene);

struct ContactPairRadius {
  std::size_t a = 0, b = 0;
  double radius = 0;
};
// The body pairs (a <= b; equal: self-contact) that have a contact law, with their l_c.
std::vector<ContactPairRadius> contact_pair_radii(const Scene& scene);

// One line on the contact speed bound for the set-up reports (call when it is finite).
std::string contact_speed_note(const StepChoice& choice);

struct Energies {
  double kinetic = 0;
  double strain = 0;
  double contact = 0;        // contact potential (contact/contact_law.hpp)
  double external_work = 0;  // work done on the bodies by loads and prescribed motion
  double dissipated = 0;     // strain energy of interactions lost when their bonds failed
  // Dissipated by the DEM contact laws' dashpots and by friction (contact/dem_law.hpp).
  double contact_damping = 0, contact_friction = 0;
  // kinetic + strain + contact + dissipated + contact_damping + contact_friction - external_work
  // - (its value at t = 0): zero for exact, undamaged dynamics.
  double balance_error = 0;
};

// Where model breakdown was first seen: inverted tetrahedra (3D) or triangles (2D bodies),
// whose current signed volume (area) has the sign opposite to the reference one. The energy
// uses |v|, so an inverted set resists no more than an upright one (Body::inversion_penalty).
// Counted in every evaluation with energy (history rows and field frames), not every step.
struct InversionRecord {
  long long step = -1;  // -1: none seen so far
  double time = 0;
  std::string body;
  std::uint64_t count = 0;  // that body's inverted sets then
};

// Whether a body's strain measure stiffens in compression (Seth-Hill m <= 0): its stable step is
// re-estimated at the current state during the run (THEORY.md section 6).
bool stiffens_in_compression(const Body& b);

class Distribution;
class ContactGhosts;

class Simulation {
 public:
  explicit Simulation(Scene& scene);
  // A distributed run (distribution.hpp): `local` is this rank's part of the scene
  // (distribute_scene). Every rank constructs and advances its Simulation in step; the energies,
  // counts and guards are over all ranks (summed in rank order: the same on every rank), and
  // max_damage is a collective.
  Simulation(Scene& local, std::unique_ptr<Distribution> distribution);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;
  // Null for a run in one process or on the replicated scheme.
  Distribution* distribution() const { return distribution_.get(); }
  // A distributed run: the whole scene this rank's part was cut from (distribute_scene), which
  // gather_whole() fills on rank 0 for the output and a restart reads a checkpoint into. Set
  // once, before the run's first output.
  void set_whole_scene(Scene& whole) { whole_ = &whole; }
  // Collective in a distributed run: rank 0's whole scene takes the state and bond flags of every
  // rank's owned points. Does nothing in a run without a distribution.
  void gather_whole();
  // The scene as a whole, what the output reads: scene(), or in a distributed run the whole
  // scene (on rank 0 as of the last gather_whole(); on the other ranks as it was built).
  const Scene& whole_scene() const { return whole_ ? *whole_ : scene_; }
  Scene& whole_scene() { return whole_ ? *whole_ : scene_; }

  // One step. With `with_energy`, the strain energy is evaluated at the new time (and the
  // energy guard runs). Throws InstabilityError when the guard trips.
  void advance(bool with_energy);

  double time() const { return time_; }
  long long step() const { return step_; }
  const StepChoice& step_choice() const { return step_choice_; }
  // The steps of the run: with `time.step_mode: adaptive` and time.end, the steps taken so far plus
  // those left at the current step (an estimate that grows as the step falls; it equals step()
  // once the run has reached time.end).
  long long planned_steps() const { return planned_steps_; }
  // The size of step `index` (1-based): dt, except a run to time.end whose last step is the
  // remainder (0 < it <= dt), so that the run ends exactly at time.end. With an adaptive step:
  // the step just taken for index step(), the next one for any later index.
  double step_size(long long index) const;
  // The time after the next step (the time of a run's next output).
  double next_time() const;
  bool adaptive() const { return scene_.time.adaptive_step; }
  // Adaptive steps: the smallest step the stable step asked for (+inf: none so far), how many
  // steps were taken below dt, and the stable step at the current state when last evaluated
  // (+inf: no body stiffens in compression).
  double smallest_step() const { return smallest_step_; }
  long long reduced_steps() const { return reduced_steps_; }
  double current_stable_step() const { return current_stable_; }
  // Seconds spent in the current-state stable-step bound (the guard or the adaptive step).
  double stable_step_seconds() const { return stable_step_seconds_; }
  // Energies as of the last evaluation with energy (kinetic and work are always current).
  Energies energies() const;
  // Evaluates the strain energy (and the inverted-set counts) at the current positions, for a
  // history row or summary written at a step that had no evaluation with energy (a run stopped
  // between rows). Forces, damage and the step's state are left exactly as they were, so a run
  // continued from here is the same bit for bit.
  void refresh_strain_energy();
  // Bonds broken during the run (pre-cracks not counted), in all bodies / in body b.
  std::size_t broken_bonds() const;
  std::size_t broken_bonds(std::size_t body) const;
  std::size_t precracked_bonds(std::size_t body) const { return initially_failed_[body]; }
  // The largest point damage of the bodies with damage (a distributed run's: over all ranks, as
  // of the last step; not a collective).
  double max_damage() const;
  // Whether some body has a far field; the fraction of those bodies' points evaluated exactly at
  // the last force evaluation (1 without a far field).
  bool has_far_field() const;
  double exact_fraction() const;
  // Inverted sets (each unordered tetrahedron or triangle once) as of the last evaluation with
  // energy: all bodies, or body b; the largest total seen; and the first sighting.
  std::uint64_t inverted() const;
  std::uint64_t inverted(std::size_t body) const { return inverted_[body]; }
  // The bonds, triangles and tetrahedra body b's kernel evaluated (each set once, not per
  // vertex), summed over this process's force evaluations (a restarted run counts from its
  // restart) and over the ranks: the work done, which a far field cuts where it leaves sets out.
  struct Evaluated {
    std::uint64_t bonds = 0, triangles = 0, tetrahedra = 0;
  };
  const Evaluated& evaluated(std::size_t body) const {
    return distribution_ ? books_.evaluated[body] : evaluated_[body];
  }
  std::uint64_t max_inverted() const { return max_inverted_; }
  const InversionRecord& first_inversion() const { return first_inversion_; }
  double speed_limit() const { return speed_limit_; }
  const Scene& scene() const { return scene_; }
  // Null when the scene has no contact work (contact_coupling.hpp).
  // The contact manager (on distributed memory: of this rank's owned points and their contact
  // ghosts, src/engine/contact_ghosts.hpp); null without contact work.
  const ContactManager* contact() const;
  // On distributed memory: the contact ghosts' selections so far and the most ghosts a rank has
  // held at a step (0 and 0 otherwise).
  std::uint64_t contact_ghost_selections() const;
  std::uint64_t contact_ghosts_peak() const { return books_.contact_ghosts_peak; }
  // On distributed memory: the point pairs in contact over all ranks, now and at the most.
  std::uint64_t contact_pairs() const { return books_.contact_pairs; }
  std::uint64_t contact_pairs_peak() const { return books_.contact_pairs_peak; }
  // The run's own counters, for checkpoints: restoring them together with every body's state
  // continues the run bit for bit.
  struct Counters {
    double time = 0;
    long long step = 0;
    double external_work = 0, dissipated = 0, strain_energy = 0, initial_total = 0;
    std::vector<std::size_t> initially_failed;
    // Adaptive step only (checkpoints of fixed-step runs do not hold them): the next step's
    // size, the smallest step asked for, the steps taken below dt.
    double next_dt = 0, smallest_step = std::numeric_limits<double>::infinity();
    long long reduced_steps = 0;
  };
  Counters counters() const;
  void restore(const Counters& counters);
  // The contact manager's springs and dissipation, for checkpoints (call when contact() is set).
  void restore_contact(const ContactManager::HistoryState& state);
  // What a checkpoint keeps of the contact (null manager: nothing); on distributed memory with
  // the dissipation summed over the ranks.
  ContactManager::HistoryState contact_history() const;
  Scene& scene() { return scene_; }
  // Wall time spent in the bodies' own forces (internal and external), for the contact benchmark.
  double body_force_seconds() const { return body_force_seconds_; }

 private:
  void evaluate_forces(bool with_energy);
  // A distributed run: the ranks' energies and counts summed into books_ (a collective, at the
  // same point on every rank; the strain energy and inverted sets only after an evaluation with
  // energy).
  void reduce_books(bool with_energy);
  // The guard's message for the point of body `index` that moves fastest (largest squared speed
  // `worst`, or not finite), as every rank sees it in a distributed run.
  [[noreturn]] void report_instability(std::size_t index, double worst, std::size_t point,
                                       const Vec3& reference, bool finite, double dt);
  void check_energy() const;
  // For bodies whose strain measure stiffens in compression (m <= 0): the stable step at the
  // current state against dt, after every force evaluation (throws InstabilityError when dt
  // exceeds it).
  void check_stable_step();
  // The smallest current-state stable step over the bodies that stiffen in compression (with
  // their contact stiffness), and where: +inf when there are none.
  struct CurrentStep {
    double dt = std::numeric_limits<double>::infinity();
    std::size_t body = 0, point = 0;
    // The adaptive step's kinematic limit (simulation.cpp shrink_fraction): +inf when nothing
    // shrinks.
    double kinematic = std::numeric_limits<double>::infinity();
  };
  CurrentStep current_step();
  // Adaptive step: the size of the next step from the current stable step, clipped so that a
  // run to time.end lands on it; updates planned_steps_.
  void plan_next_step(const CurrentStep& now);
  // Throws InstabilityError: the next step falls below time.smallest_step (floor).
  [[noreturn]] void report_step_collapse(const CurrentStep& now, double floor) const;
  // time.smallest_step's default, a fraction of dt: 1e12 steps per dt are no run.
  static constexpr double kSmallestStepFraction = 1e-12;
  void clip_next_step();  // next_dt_ and planned_steps_ from next_choice_ and the time left

  Scene& scene_;
  StepChoice step_choice_;
  long long planned_steps_ = 0;
  double last_dt_ = 0;      // the last step's size in a run to time.end; 0 for a run of N steps
  double origin_time_ = 0;  // time_ = origin_time_ + (step_ - origin_step_) dt
  long long origin_step_ = 0;
  double time_ = 0;
  long long step_ = 0;
  double external_work_ = 0;
  double dissipated_ = 0;
  double strain_energy_ = 0;
  double initial_total_ = 0;
  // The work the loads do over the last kick (dt / 2 at the end-of-step velocities): the energy
  // guard's reference counts it (a load ramping up from zero has done no work by the first step's
  // drift, yet the step's last kick gave the points their kinetic energy).
  double kick_work_ = 0;
  std::vector<std::size_t> initially_failed_;
  std::vector<std::uint64_t> inverted_;
  std::uint64_t max_inverted_ = 0;
  InversionRecord first_inversion_;
  double speed_limit_ = 0;
  // Per body: its contact stiffness bound (contact_stiffness_bounds), for check_stable_step.
  std::vector<double> contact_stiffness_;
  // Per body: the smallest l_c of the contact pairs it is in (+inf: none).
  std::vector<double> contact_radius_;
  std::unique_ptr<ContactManager> contact_;
  std::unique_ptr<ContactGhosts> contact_ghosts_;  // distributed memory's contact instead
  double body_force_seconds_ = 0;
  double stable_step_seconds_ = 0;
  // Adaptive step: the next step, the one just taken, and the statistics (see smallest_step()).
  double next_choice_ = 0;  // min(dt, safety x current stable step), before clip_next_step
  double next_dt_ = 0, taken_dt_ = 0;
  double smallest_step_ = std::numeric_limits<double>::infinity();
  long long reduced_steps_ = 0;
  double current_stable_ = std::numeric_limits<double>::infinity();
  // evaluate_forces' per-body buffers, kept between steps: a time step allocates nothing
  // (tests/allocation/).
  std::vector<double> step_dissipated_, step_strain_;
  std::vector<std::size_t> small_bodies_, large_bodies_;
  std::vector<PointSet> point_sets_;
  // The sum over ranks of the bodies whose force work is shared (force_sharing.hpp).
  ForceSharingBuffers sharing_;
  // A distributed run (distribution.hpp): external_work_, dissipated_, strain_energy_ and
  // inverted_ hold this rank's shares; books_ the sums over ranks. failed_: per body, the failed
  // bonds this rank books (at their lower ends).
  std::unique_ptr<Distribution> distribution_;
  struct Books {
    double external_work = 0, dissipated = 0, strain = 0, kinetic = 0, max_damage = 0;
    double kick_work = 0;
    double contact = 0;  // contact energy, summed over the ranks' owned points
    double contact_damping = 0, contact_friction = 0;  // dissipated by contact, summed likewise
    std::uint64_t contact_ghosts_peak = 0;
    std::uint64_t contact_pairs = 0, contact_pairs_peak = 0;  // point pairs in contact, all ranks
    std::vector<std::uint64_t> inverted;
    std::vector<std::size_t> failed;
    std::vector<Evaluated> evaluated;
  } books_;
  std::vector<Evaluated> evaluated_, step_evaluated_;  // this rank's: all steps, the last one
  std::vector<std::size_t> failed_;
  std::vector<double> book_values_;
  Scene* whole_ = nullptr;
  double kinetic_energy() const;  // this process's points (a distributed run: its owned ones)
};

}  // namespace ckpd
