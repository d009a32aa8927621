#pragma once
// The reference kernel: every point walks its own family (point_kernel.hpp), so every bond is
// computed twice, every triangle three times and every tetrahedron four times. Plain and slow;
// the optimised kernels (symmetric_kernel.hpp, both paths) are tested and benchmarked against
// it. Linked by the tests and benchmarks only: the engine never calls it.
// With ForceForm::energy_consistent (a CKPD body), each point's family scatters the gradient of
// its share of the total energy to all the vertices of its sets (THEORY.md section 2b); serial.
#include "bodies/body.hpp"
#include "bodies/point_kernel.hpp"

namespace ckpd {

// All points: body.force_density = b_int (overwritten); with `with_energy`, also
// body.strain_energy_density (the own-family W1/2 + W2/3 + W3/4 in both force forms).
void compute_internal_force(Body& body, bool with_energy);

}  // namespace ckpd
