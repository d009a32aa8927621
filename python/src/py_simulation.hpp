#pragma once
// The Python Simulation: a case loaded like `ckpd run`'s, stepped through the same RunDriver
// (so an output folder gets the same history, fields and summary), with numpy views of the
// bodies' state and the conditions' values open to change between steps.
#include <pybind11/pybind11.h>

#include <memory>
#include <string>
#include <vector>

#include "src/engine/simulation.hpp"
#include "src/output/run_driver.hpp"

namespace ckpd::python {

// A condition of the case, in the order of its `conditions` list.
struct ConditionRef {
  std::size_t body = 0;   // index into the scene's bodies
  std::size_t local = 0;  // index into that body's conditions
  std::string type;
  std::string body_name;
};

class PySimulation {
 public:
  // `out`, `restart`: None or a path (str or os.PathLike).
  PySimulation(const pybind11::handle& case_source, const pybind11::handle& overrides,
               const pybind11::handle& out, const pybind11::handle& restart, int threads,
               bool progress);

  // Runs to step `target` (<= the planned steps), calling `callback(sim)` every `every` steps
  // (after the step; stops when it returns False). Returns the number of steps done.
  long long run_to(long long target, const pybind11::object& callback, long long every,
                   const pybind11::object& self);
  // The step a time is reached at (the first step whose time is >= until).
  long long step_at(double until) const;

  Simulation& sim() { return *sim_; }
  const Simulation& sim() const { return *sim_; }
  Scene& scene() { return *scene_; }
  RunDriver& driver() { return *driver_; }
  const std::vector<ConditionRef>& conditions() const { return conditions_; }
  Condition& condition(std::size_t i);
  const std::string& status() const { return status_; }
  bool ended() const { return ended_; }
  // Ends the run with this status (history row, summary.json) unless it has ended.
  void finish(const std::string& status, const std::string& message);
  void apply_threads() const;
  // Velocities written from Python between steps change the kinetic energy outside the
  // integrator: the change is booked as external work (energy balance and guard stay true).
  void book_velocity_writes();

 private:
  std::unique_ptr<Scene> scene_;
  std::unique_ptr<Simulation> sim_;
  std::unique_ptr<RunDriver> driver_;
  std::vector<ConditionRef> conditions_;
  int threads_ = 0;
  std::string status_ = "ready";
  bool ended_ = false;             // unstable or tunnelling: no more steps
  double kinetic_after_step_ = 0;  // as the last step (or the set-up) left it
};

void bind_simulation(pybind11::module_& m);

}  // namespace ckpd::python
