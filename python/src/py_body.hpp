#pragma once
// The bodies and conditions of a Python Simulation (ckpd.Body, ckpd.Condition): numpy views of
// a body's state, a condition's points and prescribed value.
#include <pybind11/pybind11.h>

#include "python/src/py_simulation.hpp"

namespace ckpd::python {

// One body of a simulation, for Python: views into its state.
struct PyBody {
  pybind11::object owner;  // the Python Simulation: keeps the scene (and every view) alive
  PySimulation* sim;
  std::size_t index;
  // The body, for a member named `what` (BusyError while another thread's call computes).
  SceneBody& scene_body(const char* what) const {
    sim->check_free(what);
    return sim->scene().bodies[index];
  }
  Body& body(const char* what) const { return scene_body(what).body; }
};

// One condition of the case.
struct PyCondition {
  pybind11::object owner;
  PySimulation* sim;
  std::size_t index;
  const ConditionRef& ref(const char* what) const {
    sim->check_free(what);
    return sim->conditions()[index];
  }
  Condition& condition(const char* what) const {
    sim->check_free(what);
    return sim->condition(index);
  }
  int dimension() const {
    return sim->scene().bodies[sim->conditions()[index].body].body.dimension;
  }
};

void bind_body(pybind11::module_& m);

}  // namespace ckpd::python
