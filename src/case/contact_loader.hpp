#pragma once
// Reads the `contact` section of a case file (THEORY.md section 5):
//
//   contact:
//     stiffness: 1.0e12      # Ccon, Pa; without it only the listed pairs interact
//     radius: 2.5e-3         # l_c, m (default: 0.75 x the larger spacing of the two bodies;
//                            # below 0.71 x a point can slip between a lattice's surface points)
//     skin: 1.0e-3           # m, broad-phase skin (default: the radius)
//     horizon: 0.012         # m, delta of 9 Ccon/(pi delta^5) for both sides (default: each
//                            # receiving body's own horizon; a rigid body uses its partner's)
//     self_contact: [disc]   # bodies whose unbonded points repel each other
//     pairs:                 # per pair: the same keys, plus enabled: false to switch one off;
//       - {bodies: [sphere, disc], radius: 2.0e-3}   # [a, a] is a's self-contact
#include "contact/contact_settings.hpp"
#include "src/engine/scene.hpp"
#include "src/input/case_node.hpp"

namespace ckpd {

// Reads the section against the scene's bodies; every error is a CaseError naming the file,
// line and key.
ContactSettings read_contact(const CaseNode& node, Scene& scene);

}  // namespace ckpd
