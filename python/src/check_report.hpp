#pragma once
// ckpd.check_case: what `ckpd check` reports of a case, as a Python dict.
#include <pybind11/pybind11.h>

namespace ckpd::python {

// Loads the case (a file or a dict, with overrides), sets it up and times `steps` steps (at most
// the planned ones) on `threads` OpenMP threads; the report as a dict. Throws CaseError for a
// bad case, InstabilityError when a timed step goes unstable.
pybind11::dict check_report(const pybind11::handle& source, const pybind11::handle& overrides,
                            long long steps, int threads);

}  // namespace ckpd::python
