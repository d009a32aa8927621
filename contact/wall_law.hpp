#pragma once
// The point contact law (contact_law.hpp) integrated over a dense rigid half-space: what a point
// at signed height h above a flat wall feels from a wall made of infinitely many rigid points.
//
// Point i at height h >= 0 above the plane z = 0, partners filling z < 0 with unit volume
// density. Each partner within l_c = L pushes i with c V^i (L - r) along (x^i - x^j)/r; by
// symmetry only the normal part survives, cos(theta) = u of the angle to the downward normal.
// In spherical coordinates about i, the partners at distance r lie beyond the plane where
// r u > h:
//
//   F(h) = c V^i int_h^L (L - r) 2 pi r^2 int_{h/r}^1 u du dr
//        = c V^i pi int_h^L (L - r)(r^2 - h^2) dr
//        = c V^i pi (L - h)^3 (L + 3 h) / 12.
//
// Below the plane (h < 0, the point has gone in) the sphere of radius |h| around i is all wall
// and pushes equally in every direction; the rest gives the same integral with |h|, so
// F(h) = F(|h|), still pushing out, and zero once the point is L deep. The potential,
// U = -int F dh with U(L) = 0:
//
//   U(h) = c V^i pi (L - h)^4 (2 L + 3 h) / 60          for 0 <= h <= L,
//   U(h) = 2 U(0) - U(|h|)                             for -L <= h < 0,
//
// equal to the pair energy c V^i V^j (L - r)^2 / 2 summed over the part of the ball beyond the
// plane (U(0) = c V^i pi L^5 / 30: half the ball). The largest stiffness |dF/dh| =
// c V^i pi h (L - h)^2 is c V^i 4 pi L^3 / 27 at h = L / 3.
//
// Functions per unit c V^i: multiply by the pair coefficient and the point's volume.
#include <cmath>
#include <numbers>

namespace ckpd {

inline double wall_force(double h, double radius) {
  const double a = std::abs(h), L = radius;
  if (a >= L) return 0;
  const double g = L - a;
  return std::numbers::pi * g * g * g * (L + 3 * a) / 12;
}

inline double wall_energy(double h, double radius) {
  const double L = radius;
  auto above = [L](double x) {
    if (x >= L) return 0.0;
    const double g = L - x;
    return std::numbers::pi * g * g * g * g * (2 * L + 3 * x) / 60;
  };
  if (h >= 0) return above(h);
  if (h <= -L) return 2 * above(0);
  return 2 * above(0) - above(-h);
}

}  // namespace ckpd
