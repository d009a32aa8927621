#pragma once
// A body restricted to some of its points: the data a process needs to evaluate the sets centred
// at its own points when it does not hold the whole body (issue 14: a rank's owned points and
// their halo, docs/SCALING.md). The symmetric kernel evaluates each bond, triangle and
// tetrahedron from its lowest-index vertex, and every vertex of a set lies in that vertex's
// family, so the sets centred at the points of a core read only the core and the core's family
// members (core_and_halo). Restricted to those points, with the bonds among them, their flags and
// every per-point quantity of the whole body (effective volumes, fullness, stiffness bound: they
// depend on a point's whole family and are copied, not recomputed), the kernel run on the
// restriction with owned_centres = the core gives each kept point the same partial force as the
// whole body's kernel with the same owned_centres: the same sets, from the same positions, in the
// same order (local indices keep the global order, so "upper" neighbours stay upper and the
// lattice stencil's slots stay valid), bit for bit at one thread.
//
// A halo point's family in the restriction is cut to the kept points: what it holds is exactly
// what the core's sets read, but the halo point is not a valid centre (its owned_centres entry is
// 0) and its interaction counts (n2, n3) are the whole body's, not its cut family's.
#include <cstdint>
#include <vector>

#include "bodies/body.hpp"

namespace ckpd {

// The points with core[i] != 0 and every member of their families, in increasing index.
std::vector<std::uint32_t> core_and_halo(const Body& body, const std::vector<std::uint8_t>& core);

struct BodyRestriction {
  Body body;                          // the kept points, numbered in increasing global index
  std::vector<std::uint32_t> global;  // local index -> index in the whole body
};

// The body restricted to `points` (strictly increasing indices of `body`): per-point data and
// state copied, the bonds among the kept points with their intact flags, the lattice stencil (if
// any) with the kept points' coordinates, the bond-only table rebuilt for the kept bonds.
// owned_centres is copied where the body has one (the caller usually sets it to the core), and
// so is booked_points (a rank sets it to its owned points: Body::booked_points).
// Throws std::invalid_argument for indices out of order or range, and for a model with
// per-point data of its own (ForceModelKernels::prepare: the state-based solid), whose restriction
// is not defined here.
BodyRestriction restrict_body(const Body& body, const std::vector<std::uint32_t>& points);

}  // namespace ckpd
