#pragma once
// The summary.json parts that contact and rigid bodies add: broad- and narrow-phase counters,
// contact time, each rigid body's motion at the end, and every body's centre of mass and mean
// velocity (where the bodies of an impact went).
#include <nlohmann/json.hpp>

#include "src/engine/simulation.hpp"

namespace ckpd {

// {"active": false} when the scene has no contact work; else the counters of ContactStatistics,
// the time in contact and in the bodies' own forces, and the rigid bodies.
nlohmann::ordered_json contact_summary(const Simulation& sim);

}  // namespace ckpd
