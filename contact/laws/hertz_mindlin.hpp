#pragma once
// `hertz_mindlin`: Hertz's normal law, Mindlin's tangential stiffness, damping from a
// coefficient of restitution as LIGGGHTS' `model hertz tangential history` (Tsuji et al. 1992),
// Coulomb friction (tangential_spring.hpp).
//
// Two elastic spheres pressed together by delta (Hertz 1882; Johnson, Contact Mechanics 4.2):
// with 1/E* = (1 - nu_1^2)/E_1 + (1 - nu_2^2)/E_2 and 1/R* = 1/R_1 + 1/R_2 the contact radius is
// a = sqrt(R* delta), the pressure p(r) = p_0 sqrt(1 - r^2/a^2) with p_0 = 2 E* a / (pi R*), and
// the force its integral 2 pi p_0 a^2 / 3:
//
//   F(delta) = 4/3 E* sqrt(R*) delta^(3/2),   U(delta) = 8/15 E* sqrt(R*) delta^(5/2),
//   S_n = dF/d delta = 2 E* sqrt(R* delta).
//
// Mindlin (1949): the tangential stiffness of the same contact without slip is
// S_t = 8 G* sqrt(R* delta) with 1/G* = 2 (2 - nu_1)(1 + nu_1)/E_1 + 2 (2 - nu_2)(1 + nu_2)/E_2
// (G_k = E_k / (2 (1 + nu_k))).
//
// Impact at v_0 without damping: energy conservation m* v_0^2 / 2 = U(delta_max) gives
//
//   delta_max = (15 m* v_0^2 / (16 E* sqrt(R*)))^(2/5),
//
// and with x = delta/delta_max, delta'^2 = v_0^2 (1 - x^(5/2)), so the contact lasts
//
//   t_c = 2 delta_max / v_0 int_0^1 (1 - x^(5/2))^(-1/2) dx = 2.9432 delta_max / v_0
//
// (the integral is (2/5) B(2/5, 1/2) = 1.4716).
//
// Damping (LIGGGHTS): gamma_n = 2 sqrt(5/6) |beta| sqrt(S_n m*), beta = ln e / sqrt(ln^2 e +
// pi^2), so the damping ratio gamma_n / (2 sqrt(S_n m*)) = sqrt(5/6) |beta| does not depend on
// the overlap (Tsuji's observation that e then does not depend on v_0). The restitution this
// gives is close to e but not equal to it (the sqrt(5/6) is a fit); the linear law is the one
// whose e is exact.
//
// Points: a point pair is two spheres of radius l_c / 2 (R* = l_c / 4) unless
// `effective_radius` gives R*; a point against a mesh wall is a sphere of radius l_c on a plane
// (R* = l_c). E and nu: `youngs_modulus` and `poisson_ratio`, one value for both sides or a list
// [side of the first body, side of the second] in the pair's order (the wall's own for a wall).
#include <cmath>

namespace ckpd::hertz {

inline double effective_modulus(double e1, double nu1, double e2, double nu2) {
  return 1 / ((1 - nu1 * nu1) / e1 + (1 - nu2 * nu2) / e2);
}
inline double effective_shear_modulus(double e1, double nu1, double e2, double nu2) {
  return 1 / (2 * (2 - nu1) * (1 + nu1) / e1 + 2 * (2 - nu2) * (1 + nu2) / e2);
}
inline double force(double modulus, double radius, double overlap) {
  return 4.0 / 3 * modulus * std::sqrt(radius) * std::pow(overlap, 1.5);
}
inline double max_overlap(double modulus, double radius, double mass, double speed) {
  return std::pow(15 * mass * speed * speed / (16 * modulus * std::sqrt(radius)), 0.4);
}
// 2 int_0^1 (1 - x^(5/2))^(-1/2) dx = (4/5) B(2/5, 1/2).
inline double duration_factor() {
  return 0.8 * std::tgamma(0.4) * std::tgamma(0.5) / std::tgamma(0.9);
}

}  // namespace ckpd::hertz
