#pragma once
// Set-up warnings: a scene that is valid but probably does not do what its author meant.
// `ckpd check` prints them and a run repeats them among its set-up lines (and in run.log).
// None is an error: the scene runs as written.
#include <string>
#include <vector>

namespace ckpd {

class Simulation;

// One line each (no "warning:" prefix), in a fixed order: bodies closing on each other with no
// contact between them, a non-conserving contact rule, a body that cannot break in a case that
// asks for damage, a CKPD body whose Poisson ratio needs the three-neighbour interactions, a
// pulse or held velocity shorter than 10 steps. The simulation is the one set up from the scene
// (initial velocities applied, steps planned).
std::vector<std::string> scene_warnings(const Simulation& sim);

}  // namespace ckpd
