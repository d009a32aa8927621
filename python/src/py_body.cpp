#include "python/src/py_body.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>

#include "bodies/damage.hpp"
#include "bodies/fragments.hpp"

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

// A read-only (n, dim) view of one of a body's per-point vectors.
template <std::vector<Vec3> Body::*field>
py::array body_vector(const PyBody& b) {
  Body& body = b.body("ckpd.Body");
  return vector_view(body.*field, body.dimension, b.owner, false);
}

void bind_body_class(py::module_& m) {
  py::class_<PyBody>(
      m, "Body",
      "One body of a Simulation (Simulation.bodies[name]): its sizes and numpy "
      "arrays of its state.\n\n"
      "Units are SI. A 2D body is a slice of unit thickness: its volumes are areas "
      "(m^2), its masses and energies are per metre of thickness (kg/m, J/m) and its "
      "densities per unit area (N/m^2, J/m^2) where a 3D body's are per unit volume. "
      "The arrays named views share the engine's memory: they change as the "
      "simulation steps (copy them to keep a value) and stay valid while the "
      "Simulation lives; read them between calls, not from another thread while a "
      "call computes. Every member raises BusyError while another thread's call "
      "uses the simulation.")
      .def_property_readonly(
          "name", [](const PyBody& b) { return b.body("ckpd.Body.name").name; },
          "The body's name in the case (str).")
      .def_property_readonly(
          "dimension", [](const PyBody& b) { return b.body("ckpd.Body.dimension").dimension; },
          "2 or 3 (int): the number of columns of the (n, dim) arrays.")
      .def_property_readonly(
          "size", [](const PyBody& b) { return b.body("ckpd.Body.size").size(); },
          "The number of points n (int); len(body) is the same.")
      .def("__len__", [](const PyBody& b) { return b.body("ckpd.Body").size(); })
      .def_property_readonly(
          "spacing", [](const PyBody& b) { return b.scene_body("ckpd.Body.spacing").spacing; },
          "The point spacing dx, m (float).")
      .def_property_readonly(
          "horizon", [](const PyBody& b) { return b.body("ckpd.Body.horizon").horizon; },
          "The horizon delta, m (float): the radius of each point's family.")
      .def_property_readonly(
          "rigid",
          [](const PyBody& b) {
            const SceneBody& sb = b.scene_body("ckpd.Body.rigid");
            return sb.rigid.has_value() || sb.wall != nullptr;
          },
          "True for a rigid body or a mesh wall (no bonds; its motion is its own).")
      .def_property_readonly("reference_positions", &body_vector<&Body::reference_position>,
                             "(n, dim) reference positions, m (float64, read-only view).")
      .def_property_readonly(
          "positions",
          [](const PyBody& b) {
            const Body& body = b.body("ckpd.Body.positions");
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
          "(n, dim) current positions, m (float64): a new read-only array (reference + "
          "displacement; the engine stores no positions to view).")
      .def_property_readonly("displacements", &body_vector<&Body::displacement>,
                             "(n, dim) displacements, m (float64, read-only view).")
      .def_property_readonly(
          "velocities",
          [](const PyBody& b) {
            const SceneBody& sb = b.scene_body("ckpd.Body.velocities");
            return vector_view(b.body("ckpd.Body.velocities").velocity, sb.body.dimension, b.owner,
                               !sb.rigid && !sb.wall);
          },
          "(n, dim) velocities, m/s (float64): a writable view for steering (read-only for "
          "rigid bodies, whose motion is their own). Prescribed components are overwritten by "
          "their conditions in the next step; the kinetic energy a write adds or removes is "
          "booked as external work.")
      .def_property_readonly("accelerations", &body_vector<&Body::acceleration>,
                             "(n, dim) accelerations, m/s^2 (float64, read-only view).")
      .def_property_readonly(
          "force_density", &body_vector<&Body::force_density>,
          "(n, dim) total force density (internal + external + contact), N/m^3 (N/m^2 in 2D) "
          "(float64, read-only view). Times `volumes`: the force on each point, N (N/m in 2D).")
      .def_property_readonly(
          "strain_energy_density",
          [](const PyBody& b) {
            return scalar_view(b.body("ckpd.Body.strain_energy_density").strain_energy_density,
                               b.owner);
          },
          "(n,) strain-energy density, J/m^3 (J/m^2 in 2D) (float64, read-only view), as of the "
          "last energy evaluation: after each run() or step() call and at each callback.")
      .def_property_readonly(
          "volumes",
          [](const PyBody& b) { return scalar_view(b.body("ckpd.Body.volumes").volume, b.owner); },
          "(n,) point volumes, m^3 (areas, m^2, in 2D) (float64, read-only view).")
      .def_property_readonly(
          "damage",
          [](const PyBody& b) {
            std::vector<double> d;
            point_damage(b.body("ckpd.Body.damage"), d);
            return read_only_copy(d);
          },
          "(n,) damage per point, 1 - intact bonds / all bonds (0 to 1, float64): a new "
          "read-only array.")
      .def_property_readonly(
          "broken_bonds",
          [](const PyBody& b) {
            b.sim->check_free("ckpd.Body.broken_bonds");
            return b.sim->sim().broken_bonds(b.index);
          },
          "Bonds broken during the run so far (int; pre-cracks not counted).")
      .def_property_readonly(
          "precracked_bonds",
          [](const PyBody& b) {
            b.sim->check_free("ckpd.Body.precracked_bonds");
            return b.sim->sim().precracked_bonds(b.index);
          },
          "Bonds cut by the case's pre-cracks at set-up (int).")
      .def_property_readonly(
          "bonds", [](const PyBody& b) { return b.body("ckpd.Body.bonds").bond_count(); },
          "All bonds of the body, intact or not (int; each pair once).")
      .def(
          "fragments",
          [](const PyBody& b) {
            const FragmentCensus f = find_fragments(b.body("ckpd.Body.fragments"));
            py::dict d;
            d["count"] = f.count();
            d["labels"] = read_only_copy(f.label);
            d["sizes"] = read_only_copy(f.size);
            return d;
          },
          "fragments(self)\n--\n\n"
          "The pieces the body has broken into (points connected by intact bonds): a dict with "
          "'count' (int), 'labels' ((n,) piece index of each point) and 'sizes' (points per "
          "piece).")
      .def("__repr__", [](const PyBody& b) {
        // Name and sizes do not change while a call computes: no busy check.
        const Body& body = b.sim->scene().bodies[b.index].body;
        return "<ckpd.Body '" + body.name + "', " + std::to_string(body.dimension) + "D, " +
               std::to_string(body.size()) + " points>";
      });
}

void bind_condition_class(py::module_& m) {
  py::class_<PyCondition>(m, "Condition",
                          "One entry of the case's `conditions` list (Simulation.conditions[i], in "
                          "the case's order). Every member raises BusyError while another "
                          "thread's call uses the simulation.")
      .def_property_readonly(
          "type", [](const PyCondition& c) { return c.ref("ckpd.Condition.type").type; },
          "The condition's type in the case (str), e.g. 'velocity'.")
      .def_property_readonly(
          "body", [](const PyCondition& c) { return c.ref("ckpd.Condition.body").body_name; },
          "The name of the body it acts on (str).")
      .def_property_readonly(
          "index",
          [](const PyCondition& c) {
            c.sim->check_free("ckpd.Condition.index");
            return c.index;
          },
          "Its position in the case's `conditions` list (int, from 0).")
      .def_property_readonly(
          "points",
          [](const PyCondition& c) {
            return read_only_copy(c.condition("ckpd.Condition.points").points());
          },
          "(k,) indices of the body's points it acts on (read-only array): index the body's "
          "(n, dim) arrays with it.")
      .def_property(
          "value",
          [](const PyCondition& c) -> py::object {
            const Condition& cond = c.condition("ckpd.Condition.value");
            if (!cond.has_value()) return py::none();
            const Vec3 v = cond.value();
            py::array_t<double> a(c.dimension());
            for (int k = 0; k < c.dimension(); ++k) a.mutable_at(k) = v[k];
            return py::object(std::move(a));
          },
          [](PyCondition& c, const std::vector<double>& v) {
            Condition& cond = c.condition("ckpd.Condition.value");
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
          "The prescribed velocity of a `velocity` condition, m/s ((dim,) float64 array; None "
          "for other types). Set it (a sequence of dim finite numbers) between steps or in a "
          "callback: the next step uses it.")
      .def("__repr__", [](const PyCondition& c) {
        const ConditionRef& ref = c.sim->conditions()[c.index];
        return "<ckpd.Condition " + std::to_string(c.index) + ": " + ref.type + " on '" +
               ref.body_name + "'>";
      });
}

}  // namespace

void bind_body(py::module_& m) {
  bind_body_class(m);
  bind_condition_class(m);
}

}  // namespace ckpd::python
