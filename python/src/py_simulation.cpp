#include "python/src/py_simulation.hpp"

#include <omp.h>
#include <pybind11/stl.h>

#include <chrono>
#include <cmath>

#include "python/src/case_from_python.hpp"
#include "python/src/py_body.hpp"
#include "src/case/case_loader.hpp"
#include "src/cli/cli_options.hpp"
#include "src/output/checkpoint.hpp"

namespace py = pybind11;

namespace ckpd::python {

namespace {

py::dict energies_dict(const Energies& e) {
  py::dict d;
  d["kinetic"] = e.kinetic;
  d["strain"] = e.strain;
  d["contact"] = e.contact;
  d["external_work"] = e.external_work;
  d["dissipated"] = e.dissipated;
  d["balance_error"] = e.balance_error;
  return d;
}

py::object json_to_python(const nlohmann::ordered_json& j) {
  return py::module_::import("json").attr("loads")(j.dump());
}

// None or "" -> "", a str or os.PathLike -> its text.
std::string path_text(const py::handle& path) {
  if (path.is_none()) return "";
  return py::module_::import("os").attr("fspath")(path).cast<std::string>();
}

std::string float_text(double x) {
  return py::repr(py::float_(x)).cast<std::string>();
}

}  // namespace

int checked_threads(int threads, const char* name) {
  if (threads < 0 || threads > kMaxThreads)
    throw py::value_error(std::string(name) + ": expected 0 (all cores) to " +
                          std::to_string(kMaxThreads) + " OpenMP threads, got " +
                          std::to_string(threads));
  return threads;
}

PySimulation::PySimulation(const py::handle& case_source, const py::handle& overrides,
                           const py::handle& out_path, const py::handle& restart_path, int threads,
                           bool progress)
    : threads_(checked_threads(threads, "threads")) {
  const std::string out = path_text(out_path), restart = path_text(restart_path);
  const auto start = std::chrono::steady_clock::now();
  ResolvedCase resolved = resolve_case(case_source, overrides);
  case_name_ = resolved.name;
  if (auto list = resolved.root["conditions"]; list && list.IsSequence()) {
    for (const auto& c : list) {
      ConditionRef ref;
      ref.type = c["type"] ? c["type"].Scalar() : "";
      ref.body_name = c["body"] ? c["body"].Scalar() : "";
      conditions_.push_back(ref);
    }
  }
  {
    py::gil_scoped_release release;
    apply_threads();
    scene_ = std::make_unique<Scene>(load_scene(resolved.root, resolved.name, resolved.applied));
    // run(), run(until=) and end_time count steps of dt; an adaptive step's count is not known.
    if (scene_->time.adaptive_step)
      throw py::value_error(
          "time.step_mode: adaptive is not supported by the Python module (its run(), until= and "
          "end_time count steps of a fixed dt); run the case with `ckpd run`");
    sim_ = std::make_unique<Simulation>(*scene_);
    if (!restart.empty()) read_checkpoint(restart, *sim_);
  }
  // The loader accepted the list, so each entry names a body; its conditions are in list order.
  std::vector<std::size_t> seen(scene_->bodies.size(), 0);
  for (ConditionRef& ref : conditions_) {
    for (std::size_t b = 0; b < scene_->bodies.size(); ++b)
      if (scene_->bodies[b].body.name == ref.body_name) ref.body = b;
    ref.local = seen[ref.body]++;
  }
  RunDriverOptions o;
  o.out = out;
  o.restarted_from = restart;
  o.progress = progress;
  o.start = start;
  o.setup_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  driver_ = std::make_unique<RunDriver>(*sim_, o);
  kinetic_after_step_ = sim_->energies().kinetic;
}

PySimulation::Busy::Busy(PySimulation& s, const char* call, bool exclusive)
    : s_(s), outer_(s.busy_call_ == nullptr) {
  if (outer_) {
    s.busy_call_ = call;
    s.busy_thread_ = std::this_thread::get_id();
    return;
  }
  s.check_free(call);
  if (exclusive)
    throw std::runtime_error(std::string(call) + ": called from inside " + s.busy_call_ +
                             " (a callback); return False from the callback to stop the run, or "
                             "step once run() has returned");
}

PySimulation::Busy::~Busy() {
  if (outer_) s_.busy_call_ = nullptr;
}

void PySimulation::check_free(const char* what) const {
  if (busy_call_ != nullptr && busy_thread_ != std::this_thread::get_id())
    throw BusyError(std::string(what) + ": the simulation is busy: " + busy_call_ +
                    " is running in another thread (one call at a time per Simulation: wait for "
                    "that call to return, e.g. join its thread)");
}

void PySimulation::book_velocity_writes() {
  const double kinetic = sim_->energies().kinetic;
  if (kinetic == kinetic_after_step_) return;
  Simulation::Counters c = sim_->counters();
  c.external_work += kinetic - kinetic_after_step_;
  sim_->restore(c);
  kinetic_after_step_ = kinetic;
}

// OpenMP's own default (OMP_NUM_THREADS or all cores), read when the module is loaded, before
// any simulation has set a count.
const int default_threads = omp_get_max_threads();

void PySimulation::apply_threads() const {
  // OpenMP's thread count is per calling thread and outlives the call: set it on the thread
  // that computes, every time (threads=0 after a threads=1 simulation means the default again).
  omp_set_num_threads(threads_ > 0 ? threads_ : default_threads);
}

Condition& PySimulation::condition(std::size_t i) {
  const ConditionRef& ref = conditions_.at(i);
  return *scene_->bodies[ref.body].conditions.at(ref.local);
}

long long PySimulation::step_at(double until) const {
  if (!std::isfinite(until) || until < 0) throw py::value_error("until: expected a time >= 0");
  return static_cast<long long>(std::ceil(until / sim_->step_choice().dt - 1e-9));
}

void PySimulation::end(const std::string& status, const std::string& message) {
  ended_ = true;
  status_ = status;
  driver_->stop(status, message);
}

void PySimulation::finish_by_user(const py::handle& status, const std::string& message) {
  const std::string at = " (status '" + status_ + "' at step " + std::to_string(sim_->step()) + ")";
  if (status.is_none() && ended_) return;
  if (ended_)
    throw EndedError("Simulation.finish: the run has already ended" + at +
                     "; its summary.json stays as written");
  const std::string s =
      status.is_none() ? std::string("stopped") : py::str(status).cast<std::string>();
  const long long total = driver_->total_steps();
  if (s == "completed" && sim_->step() < total)
    throw py::value_error("Simulation.finish: status 'completed' needs the run at its last step (" +
                          std::to_string(total) + "); it is at step " +
                          std::to_string(sim_->step()) +
                          ": 'stopped' (the default) ends it here, run() goes on to the end");
  if (s != "stopped" && s != "failed" && s != "completed")
    throw py::value_error("Simulation.finish: status '" + s +
                          "': expected 'stopped' or 'failed' ('completed' once the run is at its "
                          "last step; 'unstable', 'tunnelling' and 'interrupted' are set by the "
                          "run itself)");
  end(s, message);
}

long long PySimulation::run_to(long long target, const py::object& callback, long long every,
                               const py::object& self) {
  if (ended_)
    throw EndedError("the run has ended (status '" + status_ + "' at step " +
                     std::to_string(sim_->step()) +
                     "); a finished Simulation steps no further: make a new one (restart= "
                     "continues from a checkpoint)");
  const long long total = driver_->total_steps();
  if (target > total)
    throw py::value_error("the case ends at step " + std::to_string(total) + " (t = " +
                          float_text(static_cast<double>(total) * sim_->step_choice().dt) +
                          " s); to go further, set a later time.end or more time.steps");
  if (every < 1) throw py::value_error("every: expected a positive number of steps");
  const long long first = sim_->step();
  status_ = "running";
  using clock = std::chrono::steady_clock;
  try {
    while (sim_->step() < target) {
      long long chunk_end = target;
      if (!callback.is_none()) chunk_end = std::min(target, (sim_->step() / every + 1) * every);
      book_velocity_writes();
      {
        py::gil_scoped_release release;
        apply_threads();
        auto checked = clock::now();
        while (sim_->step() < chunk_end) {
          // The energies are current wherever Python looks at them: after a chunk.
          driver_->step(sim_->step() + 1 == chunk_end);
          if (clock::now() - checked > std::chrono::milliseconds(200)) {
            py::gil_scoped_acquire acquire;
            if (PyErr_CheckSignals() != 0) throw py::error_already_set();
            checked = clock::now();
          }
        }
        kinetic_after_step_ = sim_->energies().kinetic;
      }
      if (!callback.is_none() && sim_->step() % every == 0) {
        const py::object r = callback(self);
        if (ended_) return sim_->step() - first;  // the callback called finish()
        if (!r.is_none() && !py::bool_(r)) {
          end("stopped", "stopped by the callback at step " + std::to_string(sim_->step()));
          return sim_->step() - first;
        }
      }
    }
  } catch (py::error_already_set& e) {
    if (!ended_) {
      if (e.matches(PyExc_KeyboardInterrupt)) {
        driver_->write_checkpoint();
        end("interrupted", "interrupted at step " + std::to_string(sim_->step()));
      } else {
        end("failed",
            "the callback raised at step " + std::to_string(sim_->step()) + ": " + e.what());
      }
    }
    throw;
  } catch (const TunnellingError& e) {
    end("tunnelling", e.what());
    throw;
  } catch (const InstabilityError& e) {
    end("unstable", e.what());
    throw;
  }
  if (sim_->step() >= total && sim_->step() > first) end("completed", "");
  return sim_->step() - first;
}

namespace {

// The members that read the state: each raises BusyError while another thread's call computes.
void bind_state(py::class_<PySimulation>& c) {
  c.def_property_readonly(
       "time",
       [](const PySimulation& s) {
         s.check_free("Simulation.time");
         return s.sim().time();
       },
       "The simulated time, s (float): step_number x dt.")
      .def_property_readonly(
          "dt",
          [](const PySimulation& s) {
            s.check_free("Simulation.dt");
            return s.sim().step_choice().dt;
          },
          "The time step, s (float): the case's time.dt, else time.safety x the stable step.")
      .def_property_readonly(
          "step_number",
          [](const PySimulation& s) {
            s.check_free("Simulation.step_number");
            return s.sim().step();
          },
          "The steps done so far (int; after a restart, counted from the start of the run).")
      .def_property_readonly(
          "planned_steps",
          [](const PySimulation& s) {
            s.check_free("Simulation.planned_steps");
            return s.sim().planned_steps();
          },
          "The steps the case plans (int): time.steps, or time.end / dt rounded up.")
      .def_property_readonly(
          "end_time",
          [](const PySimulation& s) {
            s.check_free("Simulation.end_time");
            return static_cast<double>(s.sim().planned_steps()) * s.sim().step_choice().dt;
          },
          "The time the case ends at, s (float): planned_steps x dt.")
      .def_property_readonly(
          "status", &PySimulation::status,
          "'ready' (no step yet), 'running' (stepped, not ended), or how the run ended, as its "
          "summary.json says: 'completed', 'stopped' (the callback returned False, or "
          "finish()), 'failed' (the callback raised, or finish('failed')), 'interrupted' "
          "(Ctrl-C), 'unstable' or 'tunnelling'. Readable at any time, from any thread.")
      .def_property_readonly(
          "out",
          [](const PySimulation& s) -> py::object {
            s.check_free("Simulation.out");
            if (s.driver().out().empty()) return py::none();
            return py::str(s.driver().out());
          },
          "The output folder (str), or None when the simulation writes no files.")
      .def_property_readonly(
          "energies",
          [](const PySimulation& s) {
            s.check_free("Simulation.energies");
            return energies_dict(s.sim().energies());
          },
          "The energies as of the last evaluation, J (J/m in 2D): a dict with 'kinetic', "
          "'strain', 'contact', 'external_work', 'dissipated' and 'balance_error' (floats). "
          "Current after each run() or step() call and at each callback.")
      .def_property_readonly(
          "broken_bonds",
          [](const PySimulation& s) {
            s.check_free("Simulation.broken_bonds");
            return s.sim().broken_bonds();
          },
          "Bonds broken so far in all bodies (int; pre-cracks not counted).")
      .def_property_readonly(
          "max_damage",
          [](const PySimulation& s) {
            s.check_free("Simulation.max_damage");
            return s.sim().max_damage();
          },
          "The largest point damage of all bodies, 0 to 1 (float).")
      .def_property_readonly(
          "bodies",
          [](py::object self) {
            PySimulation& s = self.cast<PySimulation&>();
            s.check_free("Simulation.bodies");
            py::dict d;
            for (std::size_t i = 0; i < s.scene().bodies.size(); ++i)
              d[py::str(s.scene().bodies[i].body.name)] = PyBody{self, &s, i};
            return d;
          },
          "The bodies by name, in the case's order: a dict str -> Body.")
      .def_property_readonly(
          "conditions",
          [](py::object self) {
            PySimulation& s = self.cast<PySimulation&>();
            s.check_free("Simulation.conditions");
            py::list l;
            for (std::size_t i = 0; i < s.conditions().size(); ++i)
              l.append(PyCondition{self, &s, i});
            return l;
          },
          "The case's conditions, in its order: a list of Condition.")
      .def(
          "summary",
          [](const PySimulation& s) {
            s.check_free("Simulation.summary");
            return json_to_python(s.driver().summary(s.status(), ""));
          },
          "summary(self)\n--\n\n"
          "The summary.json object as of now (a dict; written to the output folder when the run "
          "ends).");
}

std::string simulation_repr(const PySimulation& s) {
  const std::size_t n = s.scene().bodies.size();
  std::string text = "<ckpd.Simulation '" + s.case_name() + "': " + std::to_string(n) +
                     (n == 1 ? " body" : " bodies");
  try {
    s.check_free("");
  } catch (const BusyError&) {
    return text + ", busy in another thread>";
  }
  return text + ", step " + std::to_string(s.sim().step()) + " of " +
         std::to_string(s.sim().planned_steps()) + ", t = " + float_text(s.sim().time()) + " s, " +
         s.status() + ">";
}

}  // namespace

void bind_simulation(py::module_& m) {
  py::register_exception<BusyError>(m, "BusyError", PyExc_RuntimeError).attr("__doc__") =
      "Raised by a call on a Simulation (or one of its Body and Condition objects) while "
      "another thread's call uses it: one call at a time per Simulation. A RuntimeError.";
  py::class_<PySimulation> c(
      m, "Simulation",
      "A case, loaded and ready to step: run it, step it, steer it between steps, read its "
      "state as numpy arrays.\n\n"
      "With `out` it writes what `ckpd run --out` writes (history.csv, field frames, "
      "checkpoints, summary.json), the same bits. The run ends (summary.json written, no step "
      "after it) when it reaches the case's end, when a callback returns False or raises, on "
      "finish(), on Ctrl-C (a checkpoint first) or when it goes unstable. Units are SI (2D: per "
      "metre of thickness). Steps run without the GIL; one call at a time per Simulation: a "
      "call from another thread meanwhile raises BusyError.");
  c.def(py::init<const py::handle&, const py::handle&, const py::handle&, const py::handle&, int,
                 bool>(),
        py::arg("case"), py::arg("overrides") = py::none(), py::arg("out") = py::none(),
        py::arg("restart") = py::none(), py::arg("threads") = 0, py::arg("progress") = false,
        "__init__(self, case, overrides=None, out=None, restart=None, threads=0, progress=False)"
        "\n--\n\n"
        "Loads the case: `case` is a case file (str or os.PathLike) or a dict with the case "
        "file's keys; `overrides` as `ckpd run --set`: a dict {'key.path': value} or a list of "
        "'key.path=value' strings. `out`: the output folder (None: no files). `restart`: a "
        "checkpoint of this case to continue from. `threads`: OpenMP threads, 0 (all cores) to "
        "4096. `progress`: print the progress line. Raises CaseError for a bad case (the "
        "message names the key), CheckpointError for a bad checkpoint, ValueError for a bad "
        "argument.");
  c.def(
      "run",
      [](py::object self, py::object steps, py::object until, py::object callback,
         long long every) {
        PySimulation& s = self.cast<PySimulation&>();
        const PySimulation::Busy busy(s, "Simulation.run", true);
        if (!steps.is_none() && !until.is_none())
          throw py::value_error("run: give steps or until, not both");
        long long target = s.driver().total_steps();
        if (!steps.is_none()) {
          const long long n = steps.cast<long long>();
          if (n < 0) throw py::value_error("steps: expected a number >= 0");
          target = s.sim().step() + n;
        } else if (!until.is_none()) {
          target = s.step_at(until.cast<double>());
          if (target < s.sim().step())
            throw py::value_error("until: the run is already past that time");
        }
        return s.run_to(target, callback, every, self);
      },
      py::arg("steps") = py::none(), py::arg("until") = py::none(),
      py::arg("callback") = py::none(), py::arg("every") = 1,
      "run(self, steps=None, until=None, callback=None, every=1)\n--\n\n"
      "Steps the simulation: `steps` more steps, or `until` a time (s; to the first step at "
      "or after it), or (neither) to the case's end, which ends the run with status "
      "'completed'. `callback(sim)` is called every `every` steps (after the step, with the "
      "GIL: read and steer there); returning False stops the run (status 'stopped'), raising "
      "ends it (status 'failed') and propagates. Returns the number of steps done (int). "
      "Raises InstabilityError (TunnellingError) when the run goes unstable, RuntimeError "
      "after the run has ended, BusyError while another thread's call uses the simulation.");
  c.def(
      "step",
      [](py::object self) {
        PySimulation& s = self.cast<PySimulation&>();
        const PySimulation::Busy busy(s, "Simulation.step", true);
        return s.run_to(s.sim().step() + 1, py::none(), 1, self);
      },
      "step(self)\n--\n\n"
      "One step; the same as run(steps=1). Returns 1 (int).");
  c.def(
      "finish",
      [](PySimulation& s, const py::object& status, const std::string& message) {
        const PySimulation::Busy busy(s, "Simulation.finish", false);
        s.finish_by_user(status, message);
      },
      py::arg("status") = py::none(), py::arg("message") = "",
      "finish(self, status=None, message='')\n--\n\n"
      "Ends the run here: the history row of this step and summary.json with `status` and "
      "`message`; no step after it. `status`: 'stopped' (None, the default), 'failed', or "
      "'completed' when the run is at its last planned step (ValueError otherwise). With no "
      "status, finishing a run that has ended does nothing; with one, it raises RuntimeError. "
      "May be called from a callback: run() then returns after it.");
  c.def(
      "checkpoint",
      [](PySimulation& s, const py::object& where) {
        const PySimulation::Busy busy(s, "Simulation.checkpoint", false);
        const std::string path = path_text(where);
        if (!path.empty()) {
          write_checkpoint(path, s.sim());
          return path;
        }
        if (s.driver().out().empty())
          throw py::value_error("checkpoint: give a path (this simulation has no out folder)");
        s.driver().write_checkpoint();
        return s.driver().checkpoint_path();
      },
      py::arg("path") = py::none(),
      "checkpoint(self, path=None)\n--\n\n"
      "Writes a checkpoint of the current state to `path` (str or os.PathLike; None: "
      "OUT/checkpoint.h5) and returns its path (str). Simulation(case, restart=path) continues "
      "from it, bit for bit.");
  bind_state(c);
  c.def("__repr__", &simulation_repr);
}

}  // namespace ckpd::python
