#pragma once
// One point's own family (MODEL.md section 2, seed 000 eqs. 2.14, 2.22, 2.30): its force
// density b1 + b2 + b3 and its own-family energies, summed over unordered pairs and triples
// with the exact symmetric rewriting (per unordered pair the two orders give
// 2 C2 dV2 (1/A - 1/|a|) (dx^ik - dx^ij) x a, per unordered triple the six orders give
// 6 C3 dV3 (1/|V| - 1/|v|) v (q x r + r x p + p x q)). The engine uses it where one point's
// energy is needed (damage booking, the patch test); the whole-body loop over it is the
// reference kernel the optimised ones are tested against (reference/internal_force.hpp).
#include <cstdint>
#include <vector>

#include "bodies/body.hpp"
#include "bodies/family_scratch.hpp"
#include "bodies/set_law.hpp"
#include "bodies/switching_family.hpp"

namespace ckpd {

struct PointResult {
  Vec3 force_density = Vec3::Zero();  // b1 + b2 + b3
  double w1 = 0, w2 = 0, w3 = 0;      // own-family energies (ordered sums times dVn)
  // Unordered sets of this point's own family that are inverted: tetrahedra (3D) or triangles
  // (2D bodies) whose current signed volume (area) has the sign opposite to the reference one.
  std::uint32_t inverted = 0;
  double strain_energy_density() const { return w1 / 2 + w2 / 3 + w3 / 4; }
};

// One point with the body's model. Failed bonds and the pairs and triples they belong to
// contribute nothing (d1, d2, d3). With body.inversion_penalty = F > 0 each inverted ordered set
// adds 2 F |C| |v| (|a|) to the energy and its gradient to the force.
PointResult evaluate_point(const Body& body, std::size_t i, FamilyScratch& scratch);

// The same with a given model (the model's table entry).
template <class Model>
PointResult evaluate_point_of(const Model& model, const Body& body, std::size_t i,
                              FamilyScratch& s) {
  const bool pairs = Model::kTriangles && model.has_triangles();
  const bool triples = Model::kTetrahedra && model.has_tetrahedra();
  s.load(body, i, body.damage_enabled, pairs || triples);
  const double dv1 = body.dv1[i];
  const double degenerate = body.degenerate_fraction;
  PointResult r;
  Vec3 b = Vec3::Zero();
  double w1 = 0, w2 = 0, w3 = 0;
  for (std::size_t a = 0; a < s.size(); ++a) {
    const SetTerm<2> t = model.bond_term(s.ref[a], s.cur[a]);
    b += dv1 * t.force[0];
    w1 += t.energy * dv1;
  }
  if constexpr (Model::kTriangles) {
    if (pairs) {
      const double k2 = model.triangle_force_weight(body.dv2[i]);
      s.for_each_pair([&](std::size_t a, std::size_t c) {
        const SetTerm<3> t =
            model.triangle_term(s.ref[a], s.ref[c], s.cur[a], s.cur[c], degenerate);
        if (t.degenerate) return;
        r.inverted += t.inverted;
        b += k2 * t.force[0];
        w2 += k2 * t.energy;  // 2 orders x psi2
      });
    }
  }
  if constexpr (Model::kTetrahedra) {
    if (triples) {
      const double k3 = model.tetrahedron_force_weight(body.dv3[i]);
      s.for_each_triple([&](std::size_t a, std::size_t c, std::size_t d) {
        const SetTerm<4> t = model.tetrahedron_term(s.ref[a], s.ref[c], s.ref[d], s.cur[a],
                                                    s.cur[c], s.cur[d], degenerate);
        if (t.degenerate) return;
        r.inverted += t.inverted;
        b += k3 * t.force[0];
        w3 += k3 * t.energy;  // 6 orders x psi3
      });
    }
  }
  r.force_density = b;
  r.w1 = w1;
  r.w2 = w2;
  r.w3 = w3;
  return r;
}

// The part of point i's own-family energy density W1/2 + W2/3 + W3/4 that the failures flagged
// in `failing` (one flag per stored bond, the intact bonds about to fail; `ends` flags the points
// that hold one) take away: the energy of its failing bonds and of the sets they switch off (its
// own failing bonds' sets under either rule, and under DamageRule::all_edges also the sets with
// a failing edge between two members). The terms are evaluate_point_of's, called with the same
// slots in the same order, so this equals the drop of its strain_energy_density across the
// failures, without visiting the sets that stay on (switching_family.hpp;
// tests/test_failure_booking.cpp).
template <class Model>
double switched_off_energy_density_of(const Model& model, const Body& body, std::size_t i,
                                      SwitchingFamily& s, const std::vector<std::uint8_t>& failing,
                                      const std::vector<std::uint8_t>& ends) {
  const bool pairs = Model::kTriangles && model.has_triangles();
  const bool triples = Model::kTetrahedra && model.has_tetrahedra();
  s.load(body, i, failing, ends, (pairs || triples) && body.damage_rule == DamageRule::all_edges);
  const double degenerate = body.degenerate_fraction;
  double w1 = 0, w2 = 0, w3 = 0;
  s.for_each_failing_slot([&](std::size_t a) { w1 += model.bond_term(s.ref[a], s.cur[a]).energy; });
  w1 *= body.dv1[i];
  if constexpr (Model::kTriangles) {
    if (pairs) {
      s.for_each_switching_pair([&](std::size_t a, std::size_t c) {
        const SetTerm<3> t =
            model.triangle_term(s.ref[a], s.ref[c], s.cur[a], s.cur[c], degenerate);
        if (!t.degenerate) w2 += t.energy;
      });
      w2 *= model.triangle_force_weight(body.dv2[i]);
    }
  }
  if constexpr (Model::kTetrahedra) {
    if (triples) {
      s.for_each_switching_triple([&](std::size_t a, std::size_t c, std::size_t d) {
        const SetTerm<4> t = model.tetrahedron_term(s.ref[a], s.ref[c], s.ref[d], s.cur[a],
                                                    s.cur[c], s.cur[d], degenerate);
        if (!t.degenerate) w3 += t.energy;
      });
      w3 *= model.tetrahedron_force_weight(body.dv3[i]);
    }
  }
  return w1 / 2 + w2 / 3 + w3 / 4;
}

}  // namespace ckpd
