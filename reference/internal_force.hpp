#pragma once
// The reference kernel: every point walks its own family (point_kernel.hpp), so every bond is
// computed twice, every triangle three times and every tetrahedron four times. Plain and slow;
// the optimised kernels (symmetric_kernel.hpp, both paths) are tested and benchmarked against
// it. Linked by the tests and benchmarks only: the engine never calls it.
#include "bodies/body.hpp"
#include "bodies/point_kernel.hpp"

namespace ckpd {

// All points, in parallel: body.force_density = b_int (overwritten); with `with_energy`, also
// body.strain_energy_density.
void compute_internal_force(Body& body, bool with_energy);

}  // namespace ckpd
