#pragma once
// Which internal-force path a body takes, for the printed setup and summary.json: the lattice
// stencil (with its size) or the general path and why (bodies/lattice_stencil.hpp).
#include <nlohmann/json.hpp>
#include <string>

#include "bodies/body.hpp"

namespace ckpd {

// One line, e.g. "lattice stencil (61 offsets, 8832 triples, 0.25 MB)" or
// "general path (no stencil: points are not numbered in (z, y, x) lattice order)".
std::string kernel_path_note(const Body& body);

// {"path": "stencil"|"general", "stencil_bytes": N, "note": why not (general path)}.
nlohmann::ordered_json kernel_path_summary(const Body& body);

}  // namespace ckpd
