// The compiled part of the `ckpd` Python package (python/ckpd/ holds the rest): cases,
// simulations and sweeps, with the C++ errors as Python exceptions.
//
// Docstrings: each function's starts with its signature in CPython's text-signature form
// ("name(self, a=None)\n--\n\n"), so that inspect.signature and help() show the parameters
// (pybind11's own signature lines are turned off: inspect cannot read them). The argument names
// there are those of the py::arg next to them.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "ckpd_build_info.hpp"
#include "python/src/check_report.hpp"
#include "python/src/py_body.hpp"
#include "python/src/py_simulation.hpp"
#include "src/output/checkpoint.hpp"
#include "src/sweep/json_path.hpp"
#include "src/sweep/runner.hpp"
#include "src/sweep/sweep_file.hpp"

namespace py = pybind11;

namespace {

template <class E>
void exception(py::module_& m, const char* name, py::handle base, const char* doc) {
  py::register_exception<E>(m, name, base).attr("__doc__") = doc;
}

void bind_exceptions(py::module_& m) {
  // Translators are tried newest first: the subclasses after their bases.
  exception<ckpd::CaseError>(
      m, "CaseError", PyExc_ValueError,
      "A bad case, case dict, override or argument that names a case value: the message names "
      "the file and line (a dict: the key path, e.g. 'case dict: bodies[0].spacing'), the key "
      "and what was expected, as `ckpd run` prints it. A ValueError.");
  exception<ckpd::sweep::SweepError>(
      m, "SweepError", m.attr("CaseError"),
      "A bad sweep file: file, line, key and what was expected. A CaseError (so a ValueError).");
  exception<ckpd::InstabilityError>(
      m, "InstabilityError", PyExc_RuntimeError,
      "The run went unstable (the energy guard or the stable-step guard tripped): the message "
      "names the step, time, body and point. The run has ended with status 'unstable' (its "
      "history and summary.json written). A RuntimeError.");
  exception<ckpd::TunnellingError>(
      m, "TunnellingError", m.attr("InstabilityError"),
      "A body in contact moved more than half the contact distance in one step (status "
      "'tunnelling'): contact can no longer be trusted; a smaller dt helps. An "
      "InstabilityError.");
  exception<ckpd::CheckpointError>(
      m, "CheckpointError", PyExc_RuntimeError,
      "A checkpoint that cannot be read or does not belong to the case (restart=): the message "
      "names the file and what does not match. A RuntimeError.");
}

}  // namespace

PYBIND11_MODULE(_ckpd, m) {
  py::options options;
  options.disable_function_signatures();
  m.doc() = "ckpd: continuum-kinematics-based peridynamic impact simulation (compiled part)";
  m.attr("__version__") = ckpd::build::kVersion;
  bind_exceptions(m);
  ckpd::python::bind_simulation(m);
  ckpd::python::bind_body(m);

  m.def("check_case", &ckpd::python::check_report, py::arg("case"),
        py::arg("overrides") = py::none(), py::arg("steps") = 3, py::arg("threads") = 0,
        "check_case(case, overrides=None, steps=3, threads=0)\n--\n\n"
        "Checks a case as `ckpd check` does, without running it: loads it (a case file or a "
        "dict; `overrides` as in Simulation), sets it up and times `steps` steps (at most the "
        "planned ones; 0: none) on `threads` OpenMP threads (0: all cores). Returns the report "
        "as a dict: 'case' (its name), 'bodies' (a list of dicts: name, dimension, points, "
        "spacing (m), rigid; deformable bodies bonds, two_neighbour, three_neighbour, horizon "
        "(m), mass (kg; kg/m in 2D), kernel, body_data_mb; rigid ones motion and mass; "
        "far_field and mesh dicts or None), 'stable_step' (estimate (s), limiting_body, "
        "limiting_point, limiting_position (m)), 'time' (dt (s), safety, dt_from_case, "
        "planned_steps, end_time (s), step_mode), 'contact' (the contact laws' report, str), "
        "'warnings' (the set-up warnings `ckpd check` prints, a list of str), "
        "'memory' (body_data_mb, peak_rss_mb: MB) and 'timing' (setup_seconds, timed_steps, "
        "threads, seconds_per_step and projected_seconds: s, None without timed steps). Raises "
        "CaseError for a bad case, InstabilityError when a timed step goes unstable.");

  m.def(
      "_run_sweep_file",
      [](const std::string& file, const std::string& out, const std::string& program, int jobs,
         int threads, bool quiet) {
        ckpd::python::checked_threads(jobs, "jobs");
        ckpd::python::checked_threads(threads, "threads_per_run");
        const ckpd::sweep::Sweep s = ckpd::sweep::load_sweep(file);
        ckpd::sweep::RunnerOptions r;
        r.out = out;
        r.program = program;
        r.jobs = jobs;
        r.threads = threads;
        r.quiet = quiet;
        py::gil_scoped_release release;
        return ckpd::sweep::run_sweep(s, r);
      },
      py::arg("file"), py::arg("out"), py::arg("program"), py::arg("jobs") = 0,
      py::arg("threads") = 0, py::arg("quiet") = true,
      "_run_sweep_file(file, out, program, jobs=0, threads=0, quiet=True)\n--\n\n"
      "Runs a sweep file with the sweep runner (ckpd.run_sweep's engine); returns its exit "
      "status.");

  m.def(
      "_summary_value",
      [](const std::string& summary_text, const std::string& path) {
        std::string missing;
        const auto v = ckpd::sweep::find_json(nlohmann::json::parse(summary_text), path, missing);
        return v ? ckpd::sweep::json_cell(*v) : std::string();
      },
      py::arg("summary_text"), py::arg("path"),
      "_summary_value(summary_text, path)\n--\n\n"
      "A metric cell from a summary.json text, as sweep.csv has it ('' when the path is "
      "missing).");
}
