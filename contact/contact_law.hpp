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
// Which delta: THEORY.md uses the horizon of the body that receives the force, so each side of a
// pair has its own c. When the two horizons differ the two forces differ: the pair then pushes
// on its own centre of mass with (c_i - c_j)(l_c - r) V^i V^j (momentum is not conserved) and
// the forces are not conservative. The contact energy reported is then U with the mean
// coefficient (c_i + c_j)/2, and the power of the difference, (c_i - c_j)/2 (l_c - r) V^i V^j
// e . (v^i + v^j), shows up in the energy balance error. Giving the pair a `horizon` makes both
// sides use it: equal and opposite, conservative.
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
  // c = 9 Ccon / (pi delta^5) of the force that side 0 (the first body) and side 1 receive.
  double coefficient[2] = {0, 0};
  double mean_coefficient() const { return 0.5 * (coefficient[0] + coefficient[1]); }
};

// 9 Ccon / (pi delta^5).
double contact_coefficient(double stiffness, double horizon);

}  // namespace ckpd
