#pragma once
// The summary.json parts that contact and rigid bodies add: broad- and narrow-phase counters,
// contact time, and each rigid body's motion at the end.
#include <nlohmann/json.hpp>

#include "src/engine/simulation.hpp"

namespace ckpd {

// {"active": false} when the scene has no contact work; else the counters of ContactStatistics,
// the time in contact and in the bodies' own forces, and the rigid bodies.
nlohmann::ordered_json contact_summary(const Simulation& sim);

}  // namespace ckpd
