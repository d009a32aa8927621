#pragma once
// The prototype microelastic brittle (PMB) bond model (Silling and Askari 2005; LAMMPS's
// pair_style peri/pmb, examples/peri/in.peri.pmb): bonds only, each a linear spring in its
// stretch s = l/L - 1. A bond {i, j} pulls i with the force density
//   c s dx/l dV1^i = c (1/L - 1/l) dx dV1^i       (micromodulus c, N/m^6)
// and stores w = c L s^2 / 2 per ordered bond (per unit volume of both ends), so its energy
// density is W1/2 with W1 = sum w dV1. It fails for good once s exceeds the critical stretch s0.
// With c = C1 this is the CKPD bond family alone; unlike CKPD the micromodulus is the material
// constant itself (no E, nu) and no two- or three-neighbour sets are built whatever the body.
// LAMMPS's variable failure stretch (s0 - alpha s_min) is not part of it: s0 is constant.
#include <cmath>
#include <limits>

#include "bodies/set_law.hpp"

namespace ckpd {

struct PmbModel {
  static constexpr const char* kName = "pmb";
  static constexpr bool kTriangles = false, kTetrahedra = false;

  double c = 0;  // micromodulus, N/m^6 (3D), N/m^5 (2D)
  double critical_stretch = std::numeric_limits<double>::infinity();

  // The body's micromodulus is its bond constant (constants.c1; c2 = c3 = 0).
  template <class BodyT>
  static PmbModel of(const BodyT& body) {
    return {body.constants.c1, body.critical_stretch};
  }
  static constexpr bool has_triangles() { return false; }
  static constexpr bool has_tetrahedra() { return false; }
  static constexpr bool has_penalty() { return false; }

  // The force density on i is bond_coefficient dV1^i dx: c s / l = c (1/L - 1/l).
  template <class Measure>
  double bond_coefficient(const Measure& L, double l) const {
    return c * (L.inverse() - 1 / l);
  }
  double bond_stretch(double L, double l) const { return l / L - 1; }
  double bond_energy(double L, double stretch) const { return 0.5 * c * L * stretch * stretch; }
  bool bond_fails(double stretch) const { return stretch > critical_stretch; }
  SetTerm<2> bond_term(const Vec3& P, const Vec3& p) const {
    SetTerm<2> t;
    const double L = P.norm(), l = p.norm();
    t.force[0] = bond_coefficient(ReferenceMeasure{L}, l) * p;
    t.force[1] = -t.force[0];
    t.energy = bond_energy(L, bond_stretch(L, l));
    return t;
  }
  // dF_c/du_d = -(c/L) g_c g_d^T with g = (-n, n).
  SetLinearisation<2> bond_linearisation(const Vec3& P) const {
    const double L = P.norm();
    const Vec3 n = P / L;
    return {c, L, {-n, n}};
  }
};

}  // namespace ckpd
