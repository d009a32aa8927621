// The compiled part of the `ckpd` Python package (python/ckpd/ holds the rest): cases,
// simulations and sweeps, with the C++ errors as Python exceptions.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "python/src/case_from_python.hpp"
#include "python/src/py_simulation.hpp"
#include "src/case/case_loader.hpp"
#include "src/output/checkpoint.hpp"
#include "src/sweep/json_path.hpp"
#include "src/sweep/runner.hpp"
#include "src/sweep/sweep_file.hpp"

namespace py = pybind11;

PYBIND11_MODULE(_ckpd, m) {
  m.doc() = "ckpd: continuum-kinematics-based peridynamic impact simulation";
  // Translators are tried newest first: the subclasses after their bases.
  auto& case_error = py::register_exception<ckpd::CaseError>(m, "CaseError", PyExc_ValueError);
  py::register_exception<ckpd::sweep::SweepError>(m, "SweepError", case_error.ptr());
  auto& instability =
      py::register_exception<ckpd::InstabilityError>(m, "InstabilityError", PyExc_RuntimeError);
  py::register_exception<ckpd::TunnellingError>(m, "TunnellingError", instability.ptr());
  py::register_exception<ckpd::CheckpointError>(m, "CheckpointError", PyExc_RuntimeError);
  ckpd::python::bind_simulation(m);

  m.def(
      "check_case",
      [](const py::handle& source, const py::handle& overrides) {
        const ckpd::python::ResolvedCase c = ckpd::python::resolve_case(source, overrides);
        py::gil_scoped_release release;
        ckpd::load_scene(c.root, c.name, c.applied);
      },
      py::arg("case"), py::arg("overrides") = py::none(),
      "Loads the case (bodies sampled, conditions placed) and raises CaseError if it is bad");

  m.def(
      "_run_sweep_file",
      [](const std::string& file, const std::string& out, const std::string& program, int jobs,
         int threads, bool quiet) {
        if (jobs < 0 || threads < 0) throw py::value_error("jobs, threads: expected >= 0");
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
      py::arg("threads") = 0, py::arg("quiet") = true);

  m.def(
      "_summary_value",
      [](const std::string& summary_text, const std::string& path) {
        std::string missing;
        const auto v = ckpd::sweep::find_json(nlohmann::json::parse(summary_text), path, missing);
        return v ? ckpd::sweep::json_cell(*v) : std::string();
      },
      "A metric cell from a summary.json text, as sweep.csv has it ('' when the path is missing)");
}
