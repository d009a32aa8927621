#include "reference/internal_force.hpp"

namespace ckpd {

void compute_internal_force(Body& body, bool with_energy) {
  const std::size_t n = body.size();
#pragma omp parallel
  {
    FamilyScratch scratch;
    // Dynamic chunks: points near surfaces and cracks have far fewer interactions.
#pragma omp for schedule(dynamic, 32)
    for (std::size_t i = 0; i < n; ++i) {
      const PointResult r = evaluate_point(body, i, scratch);
      body.force_density[i] = r.force_density;
      if (with_energy) body.strain_energy_density[i] = r.strain_energy_density();
    }
  }
}

}  // namespace ckpd
