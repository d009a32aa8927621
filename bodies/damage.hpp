#pragma once
// Bond failure (THEORY.md section 4). Only bonds fail; the two- and three-neighbour factors d2,
// d3 follow from the bonds of the centre point (or, under DamageRule::all_edges, from all edges
// of the set) and are applied where those sets are enumerated (failed bonds are simply not
// loaded into the family scratch).
#include <cstdint>
#include <vector>

#include "bodies/body.hpp"

namespace ckpd {

// Objective bond stretch s = (l - L)/L, with dx = dX + (u_j - u_i).
inline double bond_stretch(const Vec3& dX, const Vec3& du) {
  const double L = dX.norm();
  return ((dX + du).norm() - L) / L;
}

// True when the reference segment a-b crosses the pre-crack (see Precrack for the rule).
bool segment_crosses_precrack(const Vec3& a, const Vec3& b, const Precrack& crack);

// Marks every bond that crosses the pre-crack as failed. Throws std::invalid_argument for a
// pre-crack with the wrong number of corners for the body's dimension or a degenerate one.
// Returns the number of bonds (each counted once) that it cut. When it cuts any, it turns on
// damage bookkeeping (Body::damage_enabled) so that the kernels skip the cut bonds even in a
// body without a critical stretch.
std::size_t apply_precrack(Body& body, const Precrack& crack);

// Fails, for good, every intact bond that the body's model breaks now (CKPD, PMB: its stretch
// exceeds the critical stretch), except bonds touching a no-failure point. Both stored directions
// of a bond compute the identical stretch, so they fail together. Returns the number of bonds (each
// counted once) that failed now.
std::size_t update_bond_failure(Body& body);

// update_bond_failure with energy bookkeeping: also returns the strain energy the failures
// removed, sum over the end points p of failing bonds of V^p (W^p before - W^p after), where W^p
// is p's own-family energy density W1/2 + W2/3 + W3/4. Under DamageRule::centre_bonds only the
// two ends of a bond see their sums change (d2 and d3 depend on the centre's bonds alone); under
// all_edges the sets through the bond leave the sums of all their vertices too. Each changed
// point's loss is the energy of exactly the bonds and sets that switch off (the others are not
// evaluated: point_kernel.hpp, switched_off_energy_density_of). Bond-only bodies have no such
// sets: the rule changes nothing there.
//
// Which bonds fail is decided at the current displacement u. The lost energy is booked at
// u - half_drift * velocity: with `half_drift` = dt/2 and `velocity` holding the drift velocity
// of the step just taken (kick-drift-kick velocity Verlet), that is the step's midpoint. Why:
// the integrator applies the interaction's force at the start of the step and none at its end,
// so the work it lets the interaction do is the trapezoid of those; the energy that actually
// leaves the system is the interaction's energy at the midpoint, to second order in dt. Booking
// it at the end of the step (half_drift = 0) leaves a first-order error per failure that adds
// up to a fifth of the dissipated energy at the default step (tests/test_energy_balance.cpp).
// Under DamageRule::centre_bonds the damaged model's forces are not the gradient of one potential
// when C2 or C3 is non-zero (a set stays active for vertices whose own bonds survive), so a
// balance with damage there closes only approximately; under all_edges each set is switched as a
// whole and the balance closes to second order in dt (docs/VALIDATION.md).
struct FailureUpdate {
  std::size_t failed = 0;  // bonds, each counted once
  double dissipated = 0;   // J (J/m in 2D)
};
FailureUpdate fail_overstretched_bonds(Body& body, double half_drift = 0);

// Point damage D^i = 1 - intact / all bonds of the family (0 for a point with no bonds).
void point_damage(const Body& body, std::vector<double>& damage);
double max_point_damage(const Body& body);

// Number of failed bonds, each counted once.
std::size_t failed_bond_count(const Body& body);

}  // namespace ckpd
