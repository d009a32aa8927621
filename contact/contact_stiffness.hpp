#pragma once
// The contact part of the stable-step estimate (THEORY.md section 6).
//
// Linearised, one contact pair of points couples them with the 3 x 3 block
// c V^i V^j [e e^T + (l_c - r)/r (I - e e^T)], whose norm is c V^i V^j while r >= l_c / 2 (a
// contact never gets deeper than that in a stable run: the repulsion grows linearly with depth).
// With the point masses rho V^i, the Gershgorin row sum of point i (diagonal block plus the
// off-diagonal ones) is 2 c sum_j V^j / rho: the same k_i / rho form as the bond stiffness bound
// of Body::stiffness_bound, to which it adds (row sums add). The sum runs over the partners that
// can be within l_c of i at once. Partner points sit on their body's lattice (spacing dx_J, so
// no two closer than dx_J while strains are small), so that sum is at most
// N(l_c, dx_J) max_j V^j with N the largest number of lattice sites in a ball of radius l_c:
// 2 for l_c = dx/2 (two sites on a cell edge), far fewer than the packing bound
// (2 l_c/dx + 1)^3 = 8. A point is assumed to touch one other body at a time; a point pressed
// by two bodies at once is covered by the slack of the row-sum bound (the pair mode that
// attains it needs all partners moving against i) but not by this argument.
//
// Stable is not accurate enough for contact. Bond modes near the bound are barely excited, but
// every impact excites the contact modes at full amplitude, and velocity Verlet misstates a
// mode's energy by about 1/(1 - (omega dt/2)^2): measured on two soft spheres whose step
// contact limits (tests/test_contact_collision.cpp), the bare bound at safety 0.8 gains 10 % of
// the kinetic energy in one collision, 0.7 of that step 0.3 %, half of it 0.05 %. So the contact
// term enters the estimate twice over (kContactResolution): at safety 0.8 that is 0.57 of the
// bare contact step, omega_con dt <= 1.13. Much more would buy little accuracy and hide the
// instability past the bound that the guard must catch.
#include <cstddef>
#include <vector>

#include "contact/contact_settings.hpp"

namespace ckpd {

// The largest number of sites of a square (2D) or cubic (3D) lattice of spacing `spacing` that a
// closed ball of radius `radius` can hold, over all placements of the ball. An upper bound: the
// ball centre is sampled on a grid of step spacing/32 over one cell and each sample counts the
// sites within radius plus the grid's covering radius, so no placement can hold more. Above
// radius = 4 spacing it returns the packing bound (2 radius/spacing + 1)^dimension.
std::size_t max_lattice_sites_in_ball(double radius, double spacing, int dimension);

inline constexpr double kContactResolution = 2;

// Per body, the contact stiffness k_con (N/m^3 per m, as Body::stiffness_bound) that the step
// estimate adds to every one of its points: kContactResolution x the bound 2 max over partners J
// (self included when self-contact is on) of c_{I<-J} N(l_c, dx_J) max_j V^j. Zero for bodies
// without contact. Throws like ContactSettings::law.
std::vector<double> contact_stiffness_bounds(const ContactSettings& settings,
                                             const std::vector<ContactBody>& bodies);

}  // namespace ckpd
