// `repulsive`: the seed's frictionless repulsion (contact_law.hpp, wall_law.hpp), the default,
// with one pair coefficient symmetric in the two bodies (the harmonic mean of their own), so that
// it conserves momentum and energy between bodies of different horizons. It keeps its own path in
// the contact manager. `repulsive_own_horizon` is the seed's rule, each receiver its own
// coefficient: not conserving where the horizons differ, kept to reproduce the seed.
#include "contact/contact_law.hpp"
#include "contact/dem_law.hpp"

namespace ckpd {
namespace {

std::shared_ptr<const DemLaw> seed_path(const LawInputs&) {
  return std::shared_ptr<const DemLaw>();
}

const bool registered = register_law(
    "repulsive",
    {"the seed's repulsion c (l_c - r) V^i V^j with one pair coefficient c, the harmonic mean of "
     "the two bodies' 9 Ccon/(pi delta^5); no friction",
     {},
     true,
     seed_path});

const bool own_horizon_registered = register_law(
    kOwnHorizonLaw,
    {"the seed's rule: each receiver uses its own 9 Ccon/(pi delta^5); does NOT conserve "
     "momentum or energy between bodies of different horizons (reproducing the seed only)",
     {},
     true,
     seed_path});

}  // namespace
}  // namespace ckpd
