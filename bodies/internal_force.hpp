#pragma once
// CKPD internal force density b1 + b2 + b3 (THEORY.md section 2, seed 000 eqs. 2.14, 2.22, 2.30)
// summed over unordered pairs and triples with the exact symmetric rewriting: per unordered pair
// the two orders give 2 C2 dV2 (1/A - 1/|a|) (dx^ik - dx^ij) x a, per unordered triple the six
// orders give 6 C3 dV3 (1/|V| - 1/|v|) v (q x r + r x p + p x q).
#include <cstdint>
#include <vector>

#include "bodies/body.hpp"
#include "bodies/family_scratch.hpp"

namespace ckpd {

struct PointResult {
  Vec3 force_density = Vec3::Zero();  // b1 + b2 + b3
  double w1 = 0, w2 = 0, w3 = 0;      // own-family energies (ordered sums times dVn)
  // Unordered sets of this point's own family that are inverted: tetrahedra (3D) or triangles
  // (2D bodies) whose current signed volume (area) has the sign opposite to the reference one.
  std::uint32_t inverted = 0;
  double strain_energy_density() const { return w1 / 2 + w2 / 3 + w3 / 4; }
};

// One point: its force density and own-family energies. Failed bonds and the pairs and triples
// they belong to contribute nothing (d1, d2, d3). With body.inversion_penalty = F > 0 each
// inverted ordered set adds 2 F |C| |v| (|a|) to the energy and its gradient to the force.
PointResult evaluate_point(const Body& body, std::size_t i, FamilyScratch& scratch);

// All points, in parallel: body.force_density = b_int (overwritten); with `with_energy`, also
// body.strain_energy_density.
void compute_internal_force(Body& body, bool with_energy);

// Sum over points of strain_energy_density * volume (call after an energy evaluation).
double strain_energy(const Body& body);

}  // namespace ckpd
