#include "python/src/check_report.hpp"

#include <omp.h>
#include <pybind11/stl.h>

#include <chrono>
#include <cmath>

#include "python/src/case_from_python.hpp"
#include "python/src/py_simulation.hpp"
#include "src/case/case_loader.hpp"
#include "src/cli/check_command.hpp"
#include "src/engine/contact_coupling.hpp"
#include "src/engine/scene_warnings.hpp"
#include "src/engine/simulation.hpp"
#include "src/output/kernel_report.hpp"
#include "src/output/run_output.hpp"

namespace py = pybind11;

namespace ckpd::python {

namespace {

using clock = std::chrono::steady_clock;

double seconds_since(clock::time_point t) {
  return std::chrono::duration<double>(clock::now() - t).count();
}

py::list xyz(const Vec3& v) {
  return py::cast(std::vector<double>{v.x(), v.y(), v.z()});
}

py::object mesh_dict(const std::optional<MeshInfo>& m, const Body& b) {
  if (!m) return py::none();
  py::dict d;
  d["file"] = m->file;
  d["triangles"] = m->triangles;
  d["box_min"] = xyz(m->lo);
  d["box_max"] = xyz(m->hi);
  d["closed"] = m->closed;
  d["open_edges"] = m->open_edges;
  d["volume"] = m->closed ? py::object(py::float_(m->mesh_volume)) : py::object(py::none());
  d["wall"] = m->wall;
  double sampled = 0;
  for (double v : b.volume) sampled += v;
  d["sampled_volume"] = m->wall ? py::object(py::none()) : py::object(py::float_(sampled));
  return d;
}

py::object far_field_dict(const SceneBody& sb) {
  if (!sb.far_field) return py::none();
  const FarField& ff = *sb.far_field;
  py::dict d;
  d["tolerance"] = ff.tolerance;
  d["operator_mb"] = static_cast<double>(ff.op.bytes()) / 1e6;
  d["row_classes"] = ff.op.classes;
  d["corotated"] = ff.corotated;
  d["exact_at_setup"] = ff.exact_count;
  return d;
}

py::dict body_dict(const SceneBody& sb) {
  const Body& b = sb.body;
  py::dict d;
  d["name"] = b.name;
  d["dimension"] = b.dimension;
  d["points"] = b.size();
  d["spacing"] = sb.spacing;
  d["rigid"] = sb.rigid.has_value();
  if (sb.rigid) {
    d["motion"] = sb.rigid->prescribed() ? "prescribed" : "free";
    d["mass"] = sb.rigid->prescribed() && !(sb.rigid->mass() > 0)
                    ? py::object(py::none())
                    : py::object(py::float_(sb.rigid->mass()));
  } else {
    d["bonds"] = b.bond_count();
    d["two_neighbour"] = b.total_two_neighbour();
    d["three_neighbour"] = b.total_three_neighbour();
    d["horizon"] = b.horizon;
    d["mass"] = b.mass();
    d["kernel"] = kernel_path_note(b);
    d["body_data_mb"] = body_megabytes(b);
  }
  d["far_field"] = far_field_dict(sb);
  d["mesh"] = mesh_dict(sb.mesh, b);
  return d;
}

}  // namespace

py::dict check_report(const py::handle& source, const py::handle& overrides, long long steps,
                      int threads) {
  checked_threads(threads, "threads");
  if (steps < 0) throw py::value_error("steps: expected a number >= 0");
  const ResolvedCase c = resolve_case(source, overrides);
  py::gil_scoped_release release;
  const int old_threads = omp_get_max_threads();
  if (threads > 0) omp_set_num_threads(threads);
  struct Restore {
    int n;
    ~Restore() { omp_set_num_threads(n); }
  } restore{old_threads};
  const auto start = clock::now();
  Scene scene = load_scene(c.root, c.name, c.applied);
  Simulation sim(scene);
  const double setup = seconds_since(start);
  const StepChoice& s = sim.step_choice();
  const long long timed = std::min(steps, sim.planned_steps());
  double per_step = 0;
  if (timed > 0) {
    const auto t0 = clock::now();
    // The last timed step checks the energy too, as `ckpd check` does.
    for (long long k = 0; k < timed; ++k) sim.advance(k + 1 == timed);
    per_step = seconds_since(t0) / static_cast<double>(timed);
  }
  py::gil_scoped_acquire acquire;
  py::dict report;
  report["case"] = c.name;
  py::list bodies;
  double megabytes = 0;
  for (const SceneBody& sb : scene.bodies) {
    bodies.append(body_dict(sb));
    if (!sb.rigid) megabytes += body_megabytes(sb.body);
    if (sb.far_field) megabytes += static_cast<double>(sb.far_field->op.bytes()) / 1e6;
  }
  report["bodies"] = bodies;
  py::dict stable;
  stable["estimate"] = s.estimate;
  stable["limiting_body"] = s.limiting_body;
  stable["limiting_point"] = s.limiting_point;
  stable["limiting_position"] = xyz(s.limiting_position);
  report["stable_step"] = stable;
  py::dict time;
  time["dt"] = s.dt;
  time["safety"] = s.safety;
  time["dt_from_case"] = s.user_dt;
  time["planned_steps"] = sim.planned_steps();
  time["end_time"] = static_cast<double>(sim.planned_steps()) * s.dt;
  time["step_mode"] = sim.adaptive() ? "adaptive" : "fixed";
  report["time"] = time;
  report["contact"] = contact_law_report(scene);
  report["warnings"] = scene_warnings(sim);
  py::dict memory;
  memory["body_data_mb"] = megabytes;
  memory["peak_rss_mb"] = peak_rss_mb();
  report["memory"] = memory;
  py::dict timing;
  timing["setup_seconds"] = setup;
  timing["timed_steps"] = timed;
  timing["threads"] = threads > 0 ? threads : old_threads;
  timing["seconds_per_step"] =
      timed > 0 ? py::object(py::float_(per_step)) : py::object(py::none());
  timing["projected_seconds"] =
      timed > 0
          ? py::object(py::float_(setup + per_step * static_cast<double>(sim.planned_steps())))
          : py::object(py::none());
  report["timing"] = timing;
  return report;
}

}  // namespace ckpd::python
