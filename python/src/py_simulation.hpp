#pragma once
// The Python Simulation: a case loaded like `ckpd run`'s, stepped through the same RunDriver
// (so an output folder gets the same history, fields and summary), with numpy views of the
// bodies' state and the conditions' values open to change between steps.
//
// One call at a time: run() and step() compute without the GIL, so another Python thread could
// otherwise step, finish or read the same state meanwhile. A call that steps, finishes or writes
// a checkpoint marks the simulation busy for its thread; a call from any other thread meanwhile
// raises BusyError. The busy marks are read and written with the GIL held.
#include <pybind11/pybind11.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "src/engine/simulation.hpp"
#include "src/output/run_driver.hpp"

namespace ckpd::python {

// Raised (as ckpd.BusyError) by a call on a Simulation that another thread's call is using.
class BusyError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Raised (as RuntimeError) by a call that needs a run that has not ended.
class EndedError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A condition of the case, in the order of its `conditions` list.
struct ConditionRef {
  std::size_t body = 0;   // index into the scene's bodies
  std::size_t local = 0;  // index into that body's conditions
  std::string type;
  std::string body_name;
};

class PySimulation {
 public:
  // `out`, `restart`: None or a path (str or os.PathLike). `threads`: 0 (OpenMP's default) to
  // kMaxThreads, else ValueError.
  PySimulation(const pybind11::handle& case_source, const pybind11::handle& overrides,
               const pybind11::handle& out, const pybind11::handle& restart, int threads,
               bool progress);

  // Marks the simulation busy with `call` ("Simulation.run") for this thread until destroyed.
  // Throws BusyError while another thread's call holds it; with `exclusive` (a call that steps)
  // also when this thread's own call holds it (a callback of run() calling step()).
  class Busy {
   public:
    Busy(PySimulation& s, const char* call, bool exclusive);
    ~Busy();
    Busy(const Busy&) = delete;
    Busy& operator=(const Busy&) = delete;

   private:
    PySimulation& s_;
    bool outer_;  // this call set the mark (not a call from inside a callback of one that did)
  };
  // Throws BusyError when another thread's call holds the simulation (for reads: `what` names
  // the member).
  void check_free(const char* what) const;

  // Runs to step `target` (<= the planned steps), calling `callback(sim)` every `every` steps
  // (after the step; stops when it returns False). Returns the number of steps done. The caller
  // holds a Busy.
  long long run_to(long long target, const pybind11::object& callback, long long every,
                   const pybind11::object& self);
  // The step a time is reached at (the first step whose time is >= until).
  long long step_at(double until) const;

  Simulation& sim() { return *sim_; }
  const Simulation& sim() const { return *sim_; }
  Scene& scene() { return *scene_; }
  const Scene& scene() const { return *scene_; }
  RunDriver& driver() { return *driver_; }
  const RunDriver& driver() const { return *driver_; }
  const std::vector<ConditionRef>& conditions() const { return conditions_; }
  Condition& condition(std::size_t i);
  const std::string& status() const { return status_; }
  const std::string& case_name() const { return case_name_; }
  bool ended() const { return ended_; }
  // Simulation.finish: ends the run with a status the user may give ("stopped", "failed", or
  // "completed" at the last planned step); None: "stopped", or nothing when the run has ended.
  void finish_by_user(const pybind11::handle& status, const std::string& message);
  void apply_threads() const;
  // Velocities written from Python between steps change the kinetic energy outside the
  // integrator: the change is booked as external work (energy balance and guard stay true).
  void book_velocity_writes();

 private:
  // Ends the run with this status: the history row, summary.json; no step after it.
  void end(const std::string& status, const std::string& message);

  std::unique_ptr<Scene> scene_;
  std::unique_ptr<Simulation> sim_;
  std::unique_ptr<RunDriver> driver_;
  std::vector<ConditionRef> conditions_;
  std::string case_name_;
  int threads_ = 0;
  std::string status_ = "ready";
  bool ended_ = false;               // summary.json written: no more steps
  double kinetic_after_step_ = 0;    // as the last step (or the set-up) left it
  const char* busy_call_ = nullptr;  // the call holding the simulation, if any
  std::thread::id busy_thread_;      // and its thread
};

// 0 (OpenMP's default) to kMaxThreads (the ckpd program's bound), else ValueError naming `name`.
int checked_threads(int threads, const char* name);

void bind_simulation(pybind11::module_& m);

}  // namespace ckpd::python
