#pragma once
// The CKPD force model (MODEL.md sections 2-4): the one place that holds its law, per
// interaction family. Kernels are plain loops over the sets of a body (CabanaPD style): they
// take the model as a template parameter and ask it, per set, for the scalar law; the sets'
// kinematics (the measure and its gradient at each vertex) are the kernels' business.
//
// Every family has a measure m with reference value R: the bond length l (L), the triangle area
// |a| (A), the tetrahedron volume |v| (|V|). The energy of one ORDERED set seen from a vertex is
//   psi = C/(2R) (m - R)^2 = C R (m/R - 1)^2 / 2
// (psi1 = C1 L s^2/2, psi2 = C2 A (|a|/A - 1)^2/2, psi3 = C3 |V| (|v|/|V| - 1)^2/2), so
//   dpsi/dm = C (m/R - 1),   d2psi/dm2 = C/R,   and dpsi/dm = 0 at the reference state.
// A vertex c of an unordered set gets the force -(orders) dV^c dpsi/dm grad_c m, where the
// orders (1 per bond end, 2 per triangle, 6 per tetrahedron) are the set's orderings in c's
// family, and the share (orders) dV^c psi / (n + 1) of its energy density W1/2 + W2/3 + W3/4.
//
// The law is written per unit force weight (`*_force_weight`: C and dV and the orders) in the
// forms the kernels evaluate, so that every kernel path computes it with the same operations:
//   bond:        c1 (1/L - 1/l), the factor of dx                   (bond_coefficient)
//   triangle:    1/A - 1/|a|, the factor of a = p x q               (triangle_coefficient)
//   tetrahedron: v/|V| - sign v, the factor of grad v               (tetrahedron_coefficient)
// and the energies as R e^2 with e = m/R - 1 (`*_energy_measure`, per unit energy weight).
// The reference measure comes as a value (general path, reference kernel) or as its inverse (the
// lattice stencil's tables): see ReferenceMeasure / InverseMeasure.
//
// Inversion penalty (BodyDefinition::inversion_penalty, F): an inverted ordered set (signed
// volume, in 2D signed area, of the opposite sign to its reference) adds 2 F |C| m to psi's
// R e^2 units, so the coefficient gains pen = 2 F |C| / C times d m/dm-factor (pen / |a| for a
// triangle, pen sign v for a tetrahedron).
//
// Damage: a bond fails for good when its stretch exceeds the critical stretch
// (bond_fails); which sets a failed bond switches off is the body's DamageRule.
//
// Strain measure (Tupek and Radovitzky, seed 002; `strain_measure: {m: M}` on a material): with
// the ratio r = m/R the law above is psi = C R e^2 / 2 with e = r - 1. The Seth-Hill family puts
//   e_m(r) = (r^(2m) - 1) / (2m),  e_0(r) = log r,   (c = r^2: e_m = (c^m - 1)/(2m))
// in its place, so dpsi/dm = C e_m(r) r^(2m - 1) (the `strain_factor`, written in place of
// r - 1 in every coefficient) and, since e_m(1) = 0 and e_m'(1) = 1 for every m, the constants
// and the linearisation at the reference state (hence the stiffness bound and stable step) are
// unchanged. m = 1/2 is e = r - 1; for m <= 0 the energy grows without bound as a set collapses
// (r -> 0). The default law (LinearStrain, m = 1/2) is its own instantiation, CkpdModel, whose
// floating-point operations are today's; any other m is CkpdSethHillModel, which evaluates
// log1p/expm1 per set. The damage rule stays the bond stretch l/L - 1 for every m.
#include <cmath>
#include <limits>

#include "bodies/material.hpp"
#include "bodies/set_law.hpp"

namespace ckpd {

// e = r - 1: today's law, evaluated in the forms written below (no pow, no log).
struct LinearStrain {
  static constexpr bool kLinear = true;
  static LinearStrain of(double /*m*/) { return {}; }
  // The slope and curvature of the law at r = 1 + d (see SethHillStrain::tangent; the stiffness
  // bound at the current state uses them, the kernels do not).
  void tangent(double d, double& slope, double& curvature) const {
    slope = d;
    curvature = 1;
  }
};

// The Seth-Hill measure e_m (m != 1/2 in use; m = 1/2 is exact here too, only slower).
struct SethHillStrain {
  static constexpr bool kLinear = false;
  double m = 0.5;
  static SethHillStrain of(double m) { return {m}; }
  // e_m(r), from d = r - 1 (log1p and expm1 keep it accurate at small strain). The measures in
  // use with m <= 0 have closed forms without exponentials (m = 0: e = log r, r^(2m - 1) = 1/r;
  // m = -1/2: e = d / r, r^(2m - 1) = 1/r^2), which the kernels' sets call once each: exp and
  // log1p were a quarter of a Kalthoff-Winkler step at m = 0.
  double strain(double d) const {
    if (m == -0.5) return d / (1 + d);
    const double lr = std::log1p(d);
    return m == 0 ? lr : std::expm1(2 * m * lr) / (2 * m);
  }
  // e_m(r) e_m'(r) = e_m(r) r^(2m - 1): dpsi/dm per unit C, in place of r - 1.
  double factor(double d) const {
    if (m == 0) return std::log1p(d) / (1 + d);
    if (m == -0.5) {
      const double ir = 1 / (1 + d);
      return d * ir * ir * ir;
    }
    const double lr = std::log1p(d);
    return std::expm1(2 * m * lr) / (2 * m) * std::exp((2 * m - 1) * lr);
  }
  // At r = 1 + d: slope = factor(d), and curvature = d/dr (e_m r^(2m - 1)) = r^(4m - 2) +
  // (2m - 1) e_m r^(2m - 2), d2psi/dm2 in units of its reference value C/R (1 at r = 1 for every
  // m; r^-2 (1 - log r) for m = 0). It grows without bound as r -> 0 for m <= 0, which is what
  // the stable-step guard watches (THEORY.md section 6). One log and two exponentials in general.
  void tangent(double d, double& slope, double& curvature) const {
    double e, g;  // e_m and r^(2m - 1)
    if (m == 0) {
      e = std::log1p(d);
      g = 1 / (1 + d);
    } else if (m == -0.5) {
      g = 1 / (1 + d);
      e = d * g;
      g *= g;
    } else {
      const double lr = std::log1p(d);
      e = std::expm1(2 * m * lr) / (2 * m);
      g = std::exp((2 * m - 1) * lr);
    }
    slope = e * g;
    curvature = g * g + (2 * m - 1) * e * g / (1 + d);
  }
};

template <class Strain>
struct CkpdLaw {
  static constexpr const char* kName = "ckpd";
  // The families this model can have (each is built only when its constant is non-zero).
  static constexpr bool kTriangles = true, kTetrahedra = true;
  // Its tetrahedron linearisation is that of the volume |v| with unit constant (below): the
  // census takes its vector loop (census.hpp, add_volume_tetrahedron_bounds).
  static constexpr bool kVolumeTetrahedra = true;

  double c1 = 0, c2 = 0, c3 = 0;
  // Inversion penalty factors in units of C: 2 F |C| / C (0 when off or when C is 0).
  double pen2 = 0, pen3 = 0;
  bool planar = false;  // 2D body: a triangle's orientation is the sign of its area's z
  double critical_stretch = std::numeric_limits<double>::infinity();
  Strain strain{};

  CkpdLaw() = default;
  CkpdLaw(const InteractionConstants& c, double inversion_penalty, bool planar_body,
          double critical, double strain_measure = 0.5)
      : c1(c.c1),
        c2(c.c2),
        c3(c.c3),
        planar(planar_body),
        critical_stretch(critical),
        strain(Strain::of(strain_measure)) {
    pen2 = c2 != 0 ? 2 * inversion_penalty * (c2 > 0 ? 1.0 : -1.0) : 0.0;
    pen3 = c3 != 0 ? 2 * inversion_penalty * (c3 > 0 ? 1.0 : -1.0) : 0.0;
  }
  // The model of a body (its constants, penalty, dimension, critical stretch, strain measure).
  template <class BodyT>
  static CkpdLaw of(const BodyT& body) {
    return CkpdLaw(body.constants, body.inversion_penalty, body.dimension == 2,
                   body.critical_stretch, body.strain_measure);
  }
  bool has_triangles() const { return c2 != 0; }
  bool has_tetrahedra() const { return c3 != 0; }
  bool has_penalty() const { return pen2 != 0 || pen3 != 0; }

  // ---- Bonds ----------------------------------------------------------------------------
  // Force on the centre i of bond {i, j}: bond_coefficient * dV1^i * dx^ij (j gets minus it
  // with its own dV1^j).
  template <class Measure>
  double bond_coefficient(const Measure& L, double l) const {
    if constexpr (Strain::kLinear) {
      return c1 * (L.inverse() - 1 / l);
    } else {
      return c1 * strain.factor(L.over(l) - 1) / l;
    }
  }
  // psi1 = C1 L s^2 / 2 of one ordered bond (s its stretch; e_m(1 + s) in its place); W1 sums
  // psi1 dV1.
  double bond_energy(double L, double stretch) const {
    if constexpr (Strain::kLinear) {
      return 0.5 * c1 * L * stretch * stretch;
    } else {
      const double e = strain.strain(stretch);
      return 0.5 * c1 * L * e * e;
    }
  }
  double bond_stretch(double L, double l) const { return l / L - 1; }
  // The damage rule: a bond fails for good once its stretch exceeds the critical stretch.
  bool bond_fails(double stretch) const { return stretch > critical_stretch; }
  // Forces on i (vertex 0) and j of bond {i, j} per unit dV1, energy psi1 per unit dV1.
  SetTerm<2> bond_term(const Vec3& P, const Vec3& p) const {
    SetTerm<2> t;
    const double L = P.norm(), l = p.norm();
    const double k = bond_coefficient(ReferenceMeasure{L}, l);
    t.force[0] = k * p;
    t.force[1] = -t.force[0];
    t.energy = bond_energy(L, bond_stretch(L, l));
    return t;
  }
  SetLinearisation<2> bond_linearisation(const Vec3& P) const {
    const double L = P.norm();
    const Vec3 n = P / L;
    return {c1, L, {-n, n}};
  }

  // ---- The tangent at the current state (the stable-step guard, current_stiffness.hpp) -------
  // At the ratio r = m/R of a set of any family, per unit C: dpsi/dm (with the penalty's
  // constant slope 2 F |C| / C of an inverted triangle or tetrahedron: `penalty` is pen2, pen3
  // or 0) and d2psi/dm2 over its reference value C/R.
  void tangent_at(double r, double penalty, double& slope, double& curvature) const {
    strain.tangent(r - 1, slope, curvature);
    slope += penalty;
  }

  // ---- Triangles (two-neighbour sets) ---------------------------------------------------
  double triangle_force_weight(double dv2) const { return 2 * c2 * dv2; }   // 2 orders
  double triangle_energy_weight(double dv2) const { return c2 * dv2 / 3; }  // share of W2/3
  // (1/A - 1/|a|): the force on the vertex with gradient G_c x a/|a| of |a| is
  // -weight (|a|/A - 1) G_c x a/|a| = -weight G_c x (coefficient a). Finite for a collapsed
  // triangle (|a| = 0). Inverted (kPenalty): + pen2 / |a|.
  template <bool kPenalty, class Measure>
  double triangle_coefficient(const Measure& A, double an, bool inverted) const {
    double f;
    if constexpr (Strain::kLinear) {
      f = A.inverse() - (an > 0 ? 1 / an : 0.0);
    } else {
      // A collapsed triangle (|a| = 0) has no direction to push along: no force, as for m = 1/2.
      f = an > 0 ? strain.factor(A.over(an) - 1) / an : 0.0;
    }
    if constexpr (kPenalty) {
      if (inverted) f += pen2 / an;
    }
    return f;
  }
  // A (|a|/A - 1)^2 (+ 2 pen2 |a| when inverted): psi2 per unit C2 / 2.
  template <bool kPenalty, class Measure>
  double triangle_energy_measure(const Measure& A, double an, bool inverted) const {
    double e = A.over(an) - 1;
    if constexpr (!Strain::kLinear) e = strain.strain(e);
    double en = A.times_square(e);
    if constexpr (kPenalty) {
      if (inverted) en += 2 * pen2 * an;
    }
    return en;
  }
  // In a plane the sign of the z component is the orientation (rotation-invariant there).
  bool triangle_inverted(double area_z, double ref_area_z) const {
    return planar && area_z * ref_area_z < 0;
  }
  // Triangle {0, 1, 2} with offsets P, Q (reference) and p, q (current) from vertex 0, per unit
  // force weight; `degenerate_fraction` as in MODEL.md section 1, from vertex 0's perspective.
  SetTerm<3> triangle_term(const Vec3& P, const Vec3& Q, const Vec3& p, const Vec3& q,
                           double degenerate_fraction) const {
    SetTerm<3> t;
    const Vec3 ref_area = P.cross(Q);
    const double A = ref_area.norm();
    if (A <= degenerate_fraction * P.norm() * Q.norm()) {
      t.degenerate = true;
      return t;
    }
    const Vec3 area = p.cross(q);
    const double an = area.norm();
    t.inverted = triangle_inverted(area.z(), ref_area.z());
    const ReferenceMeasure R{A};
    const Vec3 g = triangle_coefficient<true>(R, an, t.inverted) * area;
    t.force[0] = (q - p).cross(g);
    t.force[1] = -q.cross(g);
    t.force[2] = p.cross(g);
    t.energy = triangle_energy_measure<true>(R, an, t.inverted) / 2;
    return t;
  }
  // Gradients of |a| at the reference state: G_c x n with G_0 = P - Q... (n = a/A).
  SetLinearisation<3> triangle_linearisation(const Vec3& P, const Vec3& Q) const {
    const Vec3 area = P.cross(Q);
    const double A = area.norm();
    const Vec3 unit = area / A;
    return {1, A, {(P - Q).cross(unit), Q.cross(unit), unit.cross(P)}};
  }

  // ---- Tetrahedra (three-neighbour sets) ------------------------------------------------
  double tetrahedron_force_weight(double dv3) const { return 6 * c3 * dv3; }      // 6 orders
  double tetrahedron_energy_weight(double dv3) const { return 0.75 * c3 * dv3; }  // 6/4 psi
  // v/|V| - sign v (= (|v|/|V| - 1) sign v): vertex c gets -weight coefficient grad_c v.
  // Inverted (kPenalty): + pen3 sign v.
  template <bool kPenalty, class Measure>
  double tetrahedron_coefficient(const Measure& V, double v, bool inverted) const {
    double f;
    if constexpr (Strain::kLinear) {
      f = V.over(v) - sign_of(v);
    } else {
      // A collapsed tetrahedron (v = 0) has no direction to push along, as for triangles.
      f = v != 0 ? strain.factor(V.over(std::abs(v)) - 1) * sign_of(v) : 0.0;
    }
    if constexpr (kPenalty) {
      if (inverted) f += pen3 * sign_of(v);
    }
    return f;
  }
  // |V| (|v|/|V| - 1)^2 (without the penalty: tetrahedron_penalty_measure).
  template <class Measure>
  double tetrahedron_energy_measure(const Measure& V, double v) const {
    double e = V.over(std::abs(v)) - 1;
    if constexpr (!Strain::kLinear) e = strain.strain(e);
    return V.times_square(e);
  }
  double tetrahedron_penalty_measure(double v) const { return 2 * pen3 * std::abs(v); }
  static bool tetrahedron_inverted(double v, double signed_V) { return v * signed_V < 0; }
  // Tetrahedron {0, 1, 2, 3} with offsets P, Q, R (reference) and p, q, r (current) from
  // vertex 0, per unit force weight.
  SetTerm<4> tetrahedron_term(const Vec3& P, const Vec3& Q, const Vec3& R, const Vec3& p,
                              const Vec3& q, const Vec3& r, double degenerate_fraction) const {
    SetTerm<4> t;
    const double signed_V = P.dot(Q.cross(R)), V = std::abs(signed_V);
    if (V <= degenerate_fraction * P.norm() * Q.norm() * R.norm()) {
      t.degenerate = true;
      return t;
    }
    const Vec3 qr = q.cross(r), rp = r.cross(p), pq = p.cross(q);
    const double v = p.dot(qr);
    t.inverted = tetrahedron_inverted(v, signed_V);
    const ReferenceMeasure M{V};
    const double f = tetrahedron_coefficient<true>(M, v, t.inverted);
    t.force[0] = f * (qr + rp + pq);
    t.force[1] = -f * qr;
    t.force[2] = -f * rp;
    t.force[3] = -f * pq;
    double en = tetrahedron_energy_measure(M, v);
    if (t.inverted) en += tetrahedron_penalty_measure(v);
    t.energy = en / 2;
    return t;
  }
  // Gradients of |v| at the reference state: sign(V) (q x r, r x p, p x q) and minus their sum.
  SetLinearisation<4> tetrahedron_linearisation(const Vec3& P, const Vec3& Q, const Vec3& R) const {
    const Vec3 hj = Q.cross(R), hk = R.cross(P), hl = P.cross(Q);
    const double signed_V = P.dot(hj);
    const double s = sign_of(signed_V);
    return {1, std::abs(signed_V), {-s * (hj + hk + hl), s * hj, s * hk, s * hl}};
  }
};

// The default CKPD law (m = 1/2, today's arithmetic) and the Seth-Hill one (any m).
using CkpdModel = CkpdLaw<LinearStrain>;
using CkpdSethHillModel = CkpdLaw<SethHillStrain>;

// The same law in the energy-consistent force form (ForceForm::energy_consistent, THEORY.md
// section 2b): the per-set law is unchanged; the kernels (conservative_form<Model>()) give
// every set's force to all its vertices with the set's one weight, the sum over its active
// vertices c of V^c times the per-vertex force weight, over (n + 1) V^receiver.
template <class Law>
struct ConservativeForm : Law {
  static constexpr bool kConservative = true;
  ConservativeForm() = default;
  explicit ConservativeForm(const Law& law) : Law(law) {}
  template <class BodyT>
  static ConservativeForm of(const BodyT& body) {
    return ConservativeForm(Law::of(body));
  }
};
using CkpdConservativeModel = ConservativeForm<CkpdModel>;
using CkpdSethHillConservativeModel = ConservativeForm<CkpdSethHillModel>;

}  // namespace ckpd
