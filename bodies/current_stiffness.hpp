#pragma once
// The stiffness bound of a CKPD body at its current displacement (THEORY.md section 6, "Stable
// step in compression"): the directional Gershgorin bound of census.hpp, with every intact
// bond, triangle and tetrahedron linearised where it is now instead of at the reference state.
// For a set with measure m (l, |a|, |v|), ratio r = m/R and energy psi per unit C, the tangent
// seen by the force on vertex c is
//   d2psi/dm2 grad_c m grad_d m^T + dpsi/dm d2m/dx_c dx_d,
// so point i gets curvature(r) C/R |g_i| (sum_d |g_d|) g^_i g^_i^T from the first term (with the
// current gradients) and |dpsi/dm| sum_d |d2m/dx_i dx_d| times the identity from the second:
// a bond's d2l/dx2 is (I - n n^T)/l, a tetrahedron's d2v/dx_i dx_d the cross-product matrix of
// the edge opposite to i and d (norm: its length), a triangle's d2|a| has norm 1 per other vertex
// in a plane (plus |grad_i a| |grad_d a| / |a| out of it). At the reference state (r = 1,
// dpsi/dm = 0) it is Body::stiffness_bound to rounding; for m <= 0 it grows without bound as a
// set collapses, which the bonds' own stiffening does not see (a flat tetrahedron collapses
// while its edges are still long).
#include <vector>

#include "bodies/body.hpp"

namespace ckpd {

// bound[i]: point i's bound (N/m^3/m, as Body::stiffness_bound) at body.displacement, for a
// body of the CKPD model (any strain measure and force form). Infinite where a set has
// collapsed (r = 0 with m <= 0).
//
// shrink_time (optional), for the adaptive step: per point, the time in which the fastest
// shrinking of its bonds and sets (those the bound counts) would reach zero at the current
// velocities, min r / (-dr/dt) over those with dr/dt < 0 (+inf: none shrinks).
void ckpd_current_stiffness_bound(const Body& body, std::vector<double>& bound,
                                  std::vector<double>* shrink_time = nullptr);

namespace current_stiffness_detail {
// Whether the triangles and tetrahedra are evaluated in vector lanes where the build has them
// (true, the default); false takes the one-by-one loops of builds without them, so that tests
// compare both.
inline bool sets_in_lanes = true;
}  // namespace current_stiffness_detail

// The same shrink time over a body's intact bonds alone (any model).
void bond_shrink_time(const Body& body, std::vector<double>& shrink_time);

}  // namespace ckpd
