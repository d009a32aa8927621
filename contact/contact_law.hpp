#pragma once
// The short-range contact law of THEORY.md section 5 between two points closer than l_c:
//
//   F^i = c (l_c - r) (x^i - x^j)/r V^i V^j,   c = 9 Ccon / (pi delta^5),  r = |x^i - x^j|
//
// (F^i = V^i bcon^i: a force, N). When both sides use the same c, the pair force derives from
//
//   U = c V^i V^j (l_c - r)^2 / 2   for r < l_c, 0 beyond,
//
// since -dU/dx^i = c V^i V^j (l_c - r) dr/dx^i and dr/dx^i = (x^i - x^j)/r. U and its gradient
// vanish at r = l_c, so the force switches on without a jump. In 2D the V are areas.
//
// Which delta. Each body's own coefficient c_I = 9 Ccon/(pi delta_I^5) is the seed's penalty
// scaled to that body's horizon (THEORY.md section 5). Between two bodies the pair uses ONE
// coefficient, symmetric in the two sides (`repulsive`, the default):
//
//   c = 2 c_A c_B / (c_A + c_B)      (the harmonic mean; c_A when c_A = c_B)
//
// the two bodies' penalties as springs in series, scaled so that equal sides (self-contact, one
// resolution) keep the single body's c. The softer side governs: a fine body meeting a coarse one
// is never pushed harder than the coarse body's own penalty allows (at most 2 c_coarse), so the
// finer body is not overloaded and its stiffness does not shrink the step. Both points then
// receive equal and opposite forces from the one potential U above: linear and angular momentum
// are kept and the energy balance converges with dt. A rigid body or wall has no horizon and
// takes its partner's, so c_A = c_B there. A `horizon` given for the pair or globally makes
// both c equal to 9 Ccon/(pi delta^5) of it.
//
// The seed's own rule, `repulsive_own_horizon`, lets each receiver use its own c_I. When the
// horizons differ the two forces differ: the pair pushes on its own centre of mass with
// (c_i - c_j)(l_c - r) V^i V^j (momentum is not conserved) and the forces are not
// conservative. The contact energy reported is then U with the mean coefficient
// (c_i + c_j)/2, and the power of the difference, (c_i - c_j)/2 (l_c - r) V^i V^j
// e . (v^i + v^j), shows up in the energy balance error. It is kept to reproduce the seed only.
#include <memory>
#include <string>

namespace ckpd {

class DemLaw;

// One body pair's contact constants, resolved.
struct PairLaw {
  std::string name = "repulsive";     // the law's registered name (dem_law.hpp)
  std::shared_ptr<const DemLaw> dem;  // null: the seed law above, on its own path
  double radius = 0;                  // l_c, m
  double stiffness = 0;               // Ccon, Pa (0 for a law without it)
  double skin = 0;                    // broad-phase skin, m
  // Each side's contact radius when a DEM sphere takes part (R for the sphere; they add up to
  // l_c): the contact point of a point pair then lies where the two sides' surfaces meet,
  // p = (x^i + x^j)/2 + (r_j - r_i)/2 n (contact_manager.cpp). Both 0: the midpoint.
  double side_radius[2] = {0, 0};
  // c = 9 Ccon / (pi delta^5) of the force that side 0 (the first body) and side 1 receive.
  double coefficient[2] = {0, 0};
  double mean_coefficient() const { return 0.5 * (coefficient[0] + coefficient[1]); }
};

// 9 Ccon / (pi delta^5).
double contact_coefficient(double stiffness, double horizon);

// The pair's one coefficient from the two sides' own: their harmonic mean (a when a == b).
double pair_coefficient(double a, double b);

// The seed's non-conserving rule (each receiver its own horizon), chosen by this law name.
inline constexpr const char* kOwnHorizonLaw = "repulsive_own_horizon";

}  // namespace ckpd
