// `repulsive`: the seed's frictionless repulsion (contact_law.hpp, wall_law.hpp), the default.
// It keeps its own path in the contact manager, bit for bit as before the laws had names.
#include "contact/dem_law.hpp"

namespace ckpd {
namespace {

const bool registered = register_law(
    "repulsive", {"the seed's repulsion c (l_c - r) V^i V^j, c = 9 Ccon/(pi delta^5); no friction",
                  {},
                  true,
                  [](const LawInputs&) { return std::shared_ptr<const DemLaw>(); }});

}  // namespace
}  // namespace ckpd
