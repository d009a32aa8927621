#pragma once
// Velocity-Verlet time integration of all bodies (MODEL.md section 6), the stable-step choice,
// energy bookkeeping and the instability guard.
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>

#include "contact/contact_manager.hpp"
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
};

// Chooses dt for the scene: safety x estimate, or the case's dt (refused when it exceeds the
// estimate unless allow_unstable_dt). Throws std::invalid_argument when refused.
StepChoice choose_time_step(const Scene& scene);

struct Energies {
  double kinetic = 0;
  double strain = 0;
  double contact = 0;        // contact potential (contact/contact_law.hpp)
  double external_work = 0;  // work done on the bodies by loads and prescribed motion
  double dissipated = 0;     // strain energy of interactions lost when their bonds failed
  // kinetic + strain + contact + dissipated - external_work - (its value at t = 0): zero for
  // exact, undamaged dynamics.
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

class Simulation {
 public:
  explicit Simulation(Scene& scene);

  // One step. With `with_energy`, the strain energy is evaluated at the new time (and the
  // energy guard runs). Throws InstabilityError when the guard trips.
  void advance(bool with_energy);

  double time() const { return time_; }
  long long step() const { return step_; }
  const StepChoice& step_choice() const { return step_choice_; }
  long long planned_steps() const { return planned_steps_; }
  // Energies as of the last evaluation with energy (kinetic and work are always current).
  Energies energies() const;
  // Bonds broken during the run (pre-cracks not counted), in all bodies / in body b.
  std::size_t broken_bonds() const;
  std::size_t broken_bonds(std::size_t body) const;
  std::size_t precracked_bonds(std::size_t body) const { return initially_failed_[body]; }
  double max_damage() const;
  // Inverted sets (each unordered tetrahedron or triangle once) as of the last evaluation with
  // energy: all bodies, or body b; the largest total seen; and the first sighting.
  std::uint64_t inverted() const;
  std::uint64_t inverted(std::size_t body) const { return inverted_[body]; }
  std::uint64_t max_inverted() const { return max_inverted_; }
  const InversionRecord& first_inversion() const { return first_inversion_; }
  double speed_limit() const { return speed_limit_; }
  const Scene& scene() const { return scene_; }
  // Null when the scene has no contact work (contact_coupling.hpp).
  const ContactManager* contact() const { return contact_.get(); }
  // The run's own counters, for checkpoints: restoring them together with every body's state
  // continues the run bit for bit.
  struct Counters {
    double time = 0;
    long long step = 0;
    double external_work = 0, dissipated = 0, strain_energy = 0, initial_total = 0;
    std::vector<std::size_t> initially_failed;
  };
  Counters counters() const;
  void restore(const Counters& counters);
  Scene& scene() { return scene_; }
  // Wall time spent in the bodies' own forces (internal and external), for the contact benchmark.
  double body_force_seconds() const { return body_force_seconds_; }

 private:
  void evaluate_forces(bool with_energy);
  void check_energy() const;

  Scene& scene_;
  StepChoice step_choice_;
  long long planned_steps_ = 0;
  double time_ = 0;
  long long step_ = 0;
  double external_work_ = 0;
  double dissipated_ = 0;
  double strain_energy_ = 0;
  double initial_total_ = 0;
  std::vector<std::size_t> initially_failed_;
  std::vector<std::uint64_t> inverted_;
  std::uint64_t max_inverted_ = 0;
  InversionRecord first_inversion_;
  double speed_limit_ = 0;
  std::unique_ptr<ContactManager> contact_;
  double body_force_seconds_ = 0;
};

}  // namespace ckpd
