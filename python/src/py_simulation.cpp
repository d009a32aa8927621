#include "python/src/py_simulation.hpp"

#include <omp.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <chrono>
#include <cmath>

#include "bodies/damage.hpp"
#include "bodies/fragments.hpp"
#include "python/src/case_from_python.hpp"
#include "src/case/case_loader.hpp"
#include "src/output/checkpoint.hpp"

namespace py = pybind11;

namespace ckpd::python {

namespace {

static_assert(sizeof(Vec3) == 3 * sizeof(double), "numpy views need Vec3 to be 3 packed doubles");

// An (n, dimension) view of per-point vectors (2D bodies: x and y of the stored 3-vectors),
// kept alive by `base`.
py::array vector_view(std::vector<Vec3>& v, int dimension, const py::handle& base, bool writable) {
  py::array a(py::dtype::of<double>(),
              {static_cast<py::ssize_t>(v.size()), static_cast<py::ssize_t>(dimension)},
              {static_cast<py::ssize_t>(sizeof(Vec3)), static_cast<py::ssize_t>(sizeof(double))},
              v.empty() ? nullptr : v.data()->data(), base);
  if (!writable) a.attr("setflags")(py::arg("write") = false);
  return a;
}

py::array scalar_view(std::vector<double>& v, const py::handle& base) {
  py::array a(py::dtype::of<double>(), {static_cast<py::ssize_t>(v.size())},
              {static_cast<py::ssize_t>(sizeof(double))}, v.data(), base);
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

template <class T>
py::array read_only_copy(const std::vector<T>& v) {
  py::array_t<T> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

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

// One body of a simulation, for Python: views into its state.
struct PyBody {
  py::object owner;  // the Python Simulation: keeps the scene (and every view) alive
  PySimulation* sim;
  std::size_t index;
  SceneBody& scene_body() const { return sim->scene().bodies[index]; }
  Body& body() const { return scene_body().body; }
};

// One condition of the case.
struct PyCondition {
  py::object owner;
  PySimulation* sim;
  std::size_t index;
  Condition& condition() const { return sim->condition(index); }
  int dimension() const {
    return sim->scene().bodies[sim->conditions()[index].body].body.dimension;
  }
};

// None or "" -> "", a str or os.PathLike -> its text.
std::string path_text(const py::handle& path) {
  if (path.is_none()) return "";
  return py::module_::import("os").attr("fspath")(path).cast<std::string>();
}

}  // namespace

PySimulation::PySimulation(const py::handle& case_source, const py::handle& overrides,
                           const py::handle& out_path, const py::handle& restart_path, int threads,
                           bool progress)
    : threads_(threads) {
  const std::string out = path_text(out_path), restart = path_text(restart_path);
  const auto start = std::chrono::steady_clock::now();
  if (threads < 0) throw py::value_error("threads: expected a positive number (0: all cores)");
  ResolvedCase resolved = resolve_case(case_source, overrides);
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

void PySimulation::finish(const std::string& status, const std::string& message) {
  driver_->stop(status, message);
  status_ = status;
}

long long PySimulation::run_to(long long target, const py::object& callback, long long every,
                               const py::object& self) {
  if (ended_) throw std::runtime_error("the run has ended (" + status_ + "); nothing more to step");
  const long long total = driver_->total_steps();
  if (target > total)
    throw py::value_error("the case ends at step " + std::to_string(total) + " (t = " +
                          py::repr(py::float_(static_cast<double>(total) * sim_->step_choice().dt))
                              .cast<std::string>() +
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
        if (!r.is_none() && !py::bool_(r)) {
          finish("stopped", "stopped by the callback at step " + std::to_string(sim_->step()));
          return sim_->step() - first;
        }
      }
    }
  } catch (py::error_already_set& e) {
    if (e.matches(PyExc_KeyboardInterrupt)) {
      driver_->write_checkpoint();
      finish("interrupted", "interrupted at step " + std::to_string(sim_->step()));
    } else {
      finish("failed",
             "the callback raised at step " + std::to_string(sim_->step()) + ": " + e.what());
    }
    throw;
  } catch (const TunnellingError& e) {
    ended_ = true;
    finish("tunnelling", e.what());
    throw;
  } catch (const InstabilityError& e) {
    ended_ = true;
    finish("unstable", e.what());
    throw;
  }
  if (sim_->step() >= total && sim_->step() > first) finish("completed", "");
  return sim_->step() - first;
}

void bind_simulation(py::module_& m) {
  py::class_<PyBody>(m, "Body", "One body of a Simulation: numpy views of its state.")
      .def_property_readonly("name", [](const PyBody& b) { return b.body().name; })
      .def_property_readonly("dimension", [](const PyBody& b) { return b.body().dimension; })
      .def_property_readonly("size", [](const PyBody& b) { return b.body().size(); })
      .def("__len__", [](const PyBody& b) { return b.body().size(); })
      .def_property_readonly("spacing", [](const PyBody& b) { return b.scene_body().spacing; })
      .def_property_readonly("horizon", [](const PyBody& b) { return b.body().horizon; })
      .def_property_readonly("rigid",
                             [](const PyBody& b) {
                               return b.scene_body().rigid.has_value() ||
                                      b.scene_body().wall != nullptr;
                             })
      .def_property_readonly(
          "reference_positions",
          [](const PyBody& b) {
            return vector_view(b.body().reference_position, b.body().dimension, b.owner, false);
          },
          "(n, dim) reference positions, m (read-only view)")
      .def_property_readonly(
          "positions",
          [](const PyBody& b) {
            const Body& body = b.body();
            py::array_t<double> a(
                {static_cast<py::ssize_t>(body.size()), static_cast<py::ssize_t>(body.dimension)});
            auto r = a.mutable_unchecked<2>();
            for (std::size_t i = 0; i < body.size(); ++i) {
              const Vec3 x = body.current_position(i);
              for (int c = 0; c < body.dimension; ++c) r(i, c) = x[c];
            }
            a.attr("setflags")(py::arg("write") = false);
            return a;
          },
          "(n, dim) current positions, m: a new array (reference + displacement; the engine "
          "stores no positions to view)")
      .def_property_readonly(
          "displacements",
          [](const PyBody& b) {
            return vector_view(b.body().displacement, b.body().dimension, b.owner, false);
          },
          "(n, dim) displacements, m (read-only view)")
      .def_property_readonly(
          "velocities",
          [](const PyBody& b) {
            return vector_view(b.body().velocity, b.body().dimension, b.owner,
                               !b.scene_body().rigid && !b.scene_body().wall);
          },
          "(n, dim) velocities, m/s: a writable view for steering (read-only for rigid "
          "bodies, whose motion is their own); prescribed components are overwritten by their "
          "conditions in the next step")
      .def_property_readonly(
          "accelerations",
          [](const PyBody& b) {
            return vector_view(b.body().acceleration, b.body().dimension, b.owner, false);
          },
          "(n, dim) accelerations, m/s^2 (read-only view)")
      .def_property_readonly(
          "force_density",
          [](const PyBody& b) {
            return vector_view(b.body().force_density, b.body().dimension, b.owner, false);
          },
          "(n, dim) total force density (internal + external + contact), N/m^3 (N/m^2 in 2D) "
          "(read-only view)")
      .def_property_readonly(
          "strain_energy_density",
          [](const PyBody& b) { return scalar_view(b.body().strain_energy_density, b.owner); },
          "(n,) strain-energy density, J/m^3 (J/m^2 in 2D), as of the last energy evaluation "
          "(after each run() or step() call) (read-only view)")
      .def_property_readonly(
          "volumes", [](const PyBody& b) { return scalar_view(b.body().volume, b.owner); },
          "(n,) point volumes, m^3 (areas, m^2, in 2D) (read-only view)")
      .def_property_readonly(
          "damage",
          [](const PyBody& b) {
            std::vector<double> d;
            point_damage(b.body(), d);
            return read_only_copy(d);
          },
          "(n,) damage 1 - intact / all bonds: a new array")
      .def_property_readonly("broken_bonds",
                             [](const PyBody& b) { return b.sim->sim().broken_bonds(b.index); })
      .def_property_readonly("precracked_bonds",
                             [](const PyBody& b) { return b.sim->sim().precracked_bonds(b.index); })
      .def_property_readonly("bonds", [](const PyBody& b) { return b.body().bond_count(); })
      .def(
          "fragments",
          [](const PyBody& b) {
            const FragmentCensus f = find_fragments(b.body());
            py::dict d;
            d["count"] = f.count();
            d["labels"] = read_only_copy(f.label);
            d["sizes"] = read_only_copy(f.size);
            return d;
          },
          "Pieces connected by intact bonds: count, labels (per point), sizes (points per "
          "piece)")
      .def("__repr__", [](const PyBody& b) {
        return "<ckpd.Body '" + b.body().name + "', " + std::to_string(b.body().dimension) + "D, " +
               std::to_string(b.body().size()) + " points>";
      });

  py::class_<PyCondition>(m, "Condition", "One entry of the case's `conditions` list.")
      .def_property_readonly("type",
                             [](const PyCondition& c) { return c.sim->conditions()[c.index].type; })
      .def_property_readonly(
          "body", [](const PyCondition& c) { return c.sim->conditions()[c.index].body_name; })
      .def_property_readonly("index", [](const PyCondition& c) { return c.index; })
      .def_property_readonly(
          "points", [](const PyCondition& c) { return read_only_copy(c.condition().points()); })
      .def_property(
          "value",
          [](const PyCondition& c) -> py::object {
            if (!c.condition().has_value()) return py::none();
            const Vec3 v = c.condition().value();
            py::array_t<double> a(c.dimension());
            for (int k = 0; k < c.dimension(); ++k) a.mutable_at(k) = v[k];
            return py::object(std::move(a));
          },
          [](PyCondition& c, const std::vector<double>& v) {
            Condition& cond = c.condition();
            const ConditionRef& ref = c.sim->conditions()[c.index];
            if (!cond.has_value())
              throw py::value_error("condition " + std::to_string(c.index) + " (" + ref.type +
                                    " on '" + ref.body_name + "') has no value to change");
            if (static_cast<int>(v.size()) != c.dimension())
              throw py::value_error("value: expected " + std::to_string(c.dimension()) +
                                    " numbers (a " + std::to_string(c.dimension()) + "D body)");
            Vec3 x = Vec3::Zero();
            for (int k = 0; k < c.dimension(); ++k) {
              if (!std::isfinite(v[k])) throw py::value_error("value: expected finite numbers");
              x[k] = v[k];
            }
            cond.set_value(x);
          },
          "The prescribed velocity of a `velocity` condition, m/s (None for other types); set "
          "it between steps: the next step uses it")
      .def("__repr__", [](const PyCondition& c) {
        const ConditionRef& ref = c.sim->conditions()[c.index];
        return "<ckpd.Condition " + std::to_string(c.index) + ": " + ref.type + " on '" +
               ref.body_name + "'>";
      });

  py::class_<PySimulation>(m, "Simulation", "A case, ready to step.")
      .def(py::init<const py::handle&, const py::handle&, const py::handle&, const py::handle&, int,
                    bool>(),
           py::arg("case"), py::arg("overrides") = py::none(), py::arg("out") = py::none(),
           py::arg("restart") = py::none(), py::arg("threads") = 0, py::arg("progress") = false,
           "Loads the case (a file or a dict; overrides as --set). With `out`, writes what "
           "`ckpd run --out` writes; `restart`: a checkpoint of this case to continue from; "
           "`threads`: OpenMP threads (0: all cores); `progress`: the progress line")
      .def(
          "run",
          [](py::object self, py::object steps, py::object until, py::object callback,
             long long every) {
            PySimulation& s = self.cast<PySimulation&>();
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
          py::arg("callback") = py::none(), py::arg("every") = 1)
      .def("step",
           [](py::object self) {
             PySimulation& s = self.cast<PySimulation&>();
             return s.run_to(s.sim().step() + 1, py::none(), 1, self);
           })
      .def(
          "finish",
          [](PySimulation& s, const std::string& status, const std::string& message) {
            s.finish(status, message);
          },
          py::arg("status") = "stopped", py::arg("message") = "",
          "Ends the run here: the history row of this step and summary.json with this status")
      .def(
          "checkpoint",
          [](PySimulation& s, const py::object& where) {
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
          "Writes a checkpoint (default: OUT/checkpoint.h5); returns its path")
      .def_property_readonly("time", [](const PySimulation& s) { return s.sim().time(); })
      .def_property_readonly("dt", [](const PySimulation& s) { return s.sim().step_choice().dt; })
      .def_property_readonly("step_number", [](const PySimulation& s) { return s.sim().step(); })
      .def_property_readonly("planned_steps",
                             [](const PySimulation& s) { return s.sim().planned_steps(); })
      .def_property_readonly("end_time",
                             [](const PySimulation& s) {
                               return static_cast<double>(s.sim().planned_steps()) *
                                      s.sim().step_choice().dt;
                             })
      .def_property_readonly("status", &PySimulation::status)
      .def_property_readonly("out",
                             [](PySimulation& s) -> py::object {
                               if (s.driver().out().empty()) return py::none();
                               return py::str(s.driver().out());
                             })
      .def_property_readonly(
          "energies", [](const PySimulation& s) { return energies_dict(s.sim().energies()); })
      .def_property_readonly("broken_bonds",
                             [](const PySimulation& s) { return s.sim().broken_bonds(); })
      .def_property_readonly("max_damage",
                             [](const PySimulation& s) { return s.sim().max_damage(); })
      .def_property_readonly("bodies",
                             [](py::object self) {
                               PySimulation& s = self.cast<PySimulation&>();
                               py::dict d;
                               for (std::size_t i = 0; i < s.scene().bodies.size(); ++i)
                                 d[py::str(s.scene().bodies[i].body.name)] = PyBody{self, &s, i};
                               return d;
                             })
      .def_property_readonly("conditions",
                             [](py::object self) {
                               PySimulation& s = self.cast<PySimulation&>();
                               py::list l;
                               for (std::size_t i = 0; i < s.conditions().size(); ++i)
                                 l.append(PyCondition{self, &s, i});
                               return l;
                             })
      .def(
          "summary",
          [](PySimulation& s) { return json_to_python(s.driver().summary(s.status(), "")); },
          "The summary.json object as of now");
}

}  // namespace ckpd::python
