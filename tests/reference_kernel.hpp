#pragma once
// A plain reference for the CKPD internal force of one point, written straight from THEORY.md
// section 2 and independently of bodies/internal_force.cpp: ORDERED sums over j in H1,
// ordered pairs (j, k) and ordered triples (j, k, l), with the seed's per-order terms
//   b1 += d1 C1 (1/L - 1/l) dx^ij                                 dV1
//   b2 += d2 2 C2 dx^ik x ((1/A - 1/|a|) a),        a = dx^ij x dx^ik          dV2
//   b3 += d3 3 C3 (dx^ik x dx^il) (1/|V| - 1/|v|) v, v = (dx^ij x dx^ik).dx^il  dV3
// and the own-family energies W1, W2, W3 (ordered sums of psi1, psi2, psi3 times dVn).
// d1, d2, d3 come from the intact flags of the centre point's bonds. Slow: O(N1^3) per point.
//
// Conditioning: for a nearly flat set (kappa = L^ij L^ik L^il / |V| large; L^ij L^ik / A for a
// triangle) |V| itself is only known to about kappa * eps in double precision, so any two correct
// double-precision evaluations of that set's term differ by about kappa * eps * (|v|/|V|) times
// its scale (and the reference, which recomputes |V| for each order, by as much). Lattices have
// no such sets (kappa < 100); irregular clouds do. For sets with kappa > 100 the reference adds
// that estimate to force_allowance / energy_allowance, which tests add to their tolerance.
#include <cmath>
#include <cstdint>
#include <vector>

#include "bodies/body.hpp"

namespace ckpd_test {

struct ReferenceResult {
  ckpd::Vec3 b1 = ckpd::Vec3::Zero(), b2 = ckpd::Vec3::Zero(), b3 = ckpd::Vec3::Zero();
  double w1 = 0, w2 = 0, w3 = 0;
  std::uint64_t n1 = 0, n2 = 0, n3 = 0;              // ordered non-degenerate sets, intact or not
  double force_allowance = 0, energy_allowance = 0;  // rounding of nearly flat sets (see above)
  ckpd::Vec3 force() const { return b1 + b2 + b3; }
  double energy() const { return w1 + w2 + w3; }
};

inline constexpr double kFlat = 100;   // kappa above which a set counts as nearly flat
inline constexpr double kEps = 4e-16;  // a couple of units of double rounding

inline ReferenceResult reference_point(const ckpd::Body& body, std::size_t i) {
  using ckpd::Vec3;
  const double reach = body.horizon * (1 + 1e-12);
  const double c1 = body.constants.c1, c2 = body.constants.c2, c3 = body.constants.c3;
  const double dv1 = body.dv1[i], dv2 = body.dv2[i], dv3 = body.dv3[i];

  // The family of i with reference and current offsets and the intact flag of bond i-j.
  std::vector<Vec3> X, dX, dx;
  std::vector<double> L;
  std::vector<bool> intact;
  for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k) {
    const std::size_t j = body.family.neighbour[k];
    X.push_back(body.reference_position[j]);
    dX.push_back(body.reference_position[j] - body.reference_position[i]);
    dx.push_back(dX.back() + (body.displacement[j] - body.displacement[i]));
    L.push_back(dX.back().norm());
    intact.push_back(body.bond_intact[k] != 0);
  }
  const std::size_t n = X.size();
  auto close = [&](std::size_t a, std::size_t b) { return (X[a] - X[b]).norm() <= reach; };

  ReferenceResult r;
  for (std::size_t j = 0; j < n; ++j) {
    ++r.n1;
    if (!intact[j]) continue;
    const double l = dx[j].norm();
    r.b1 += c1 * (1 / L[j] - 1 / l) * dx[j] * dv1;
    r.w1 += c1 * L[j] * (l / L[j] - 1) * (l / L[j] - 1) / 2 * dv1;
  }

  if (c2 != 0) {
    for (std::size_t j = 0; j < n; ++j)
      for (std::size_t k = 0; k < n; ++k) {
        if (j == k || !close(j, k)) continue;
        const double A = dX[j].cross(dX[k]).norm();
        if (!(A > 1e-10 * L[j] * L[k])) continue;
        ++r.n2;
        if (!(intact[j] && intact[k])) continue;
        const Vec3 a = dx[j].cross(dx[k]);
        const double an = a.norm();
        r.b2 += 2 * c2 * dx[k].cross((1 / A - 1 / an) * a) * dv2;
        r.w2 += c2 * A * (an / A - 1) * (an / A - 1) / 2 * dv2;
        const double kappa = L[j] * L[k] / A;
        if (kappa > kFlat) {
          r.force_allowance += kEps * kappa * std::abs(2 * c2 * dv2) * dx[k].norm() * an / A;
          r.energy_allowance += kEps * kappa * std::abs(c2 * dv2) * an * an / A;
        }
      }
  }

  if (c3 != 0) {
    for (std::size_t j = 0; j < n; ++j)
      for (std::size_t k = 0; k < n; ++k) {
        if (j == k || !close(j, k)) continue;
        for (std::size_t l = 0; l < n; ++l) {
          if (l == j || l == k || !close(j, l) || !close(k, l)) continue;
          const double V = std::abs(dX[j].cross(dX[k]).dot(dX[l]));
          if (!(V > 1e-10 * L[j] * L[k] * L[l])) continue;
          ++r.n3;
          if (!(intact[j] && intact[k] && intact[l])) continue;
          const double v = dx[j].cross(dx[k]).dot(dx[l]);
          const double av = std::abs(v);
          r.b3 += 3 * c3 * dx[k].cross(dx[l]) * ((1 / V - 1 / av) * v) * dv3;
          r.w3 += c3 * V * (av / V - 1) * (av / V - 1) / 2 * dv3;
          const double kappa = L[j] * L[k] * L[l] / V;
          if (kappa > kFlat) {
            r.force_allowance +=
                kEps * kappa * std::abs(3 * c3 * dv3) * dx[k].cross(dx[l]).norm() * av / V;
            r.energy_allowance += kEps * kappa * std::abs(c3 * dv3) * av * av / V;
          }
        }
      }
  }
  return r;
}

}  // namespace ckpd_test
