#pragma once
// How full the bodies' families are, for the printed setup and summary.json: the largest raw
// beta (family volume over the full family volume) and, for bodies with `beta: capped`, how many
// points had their beta capped at 1. A cap changes the model, so it is never silent.
#include <nlohmann/json.hpp>
#include <string>

#include "bodies/body.hpp"

namespace ckpd {

// One line for the printed setup; empty when the body's beta was not capped.
std::string beta_setup_note(const Body& body);

// {"policy": "strict"|"capped", "capped_points": N, "max_raw": X}.
nlohmann::ordered_json beta_summary(const Body& body);

}  // namespace ckpd
