#pragma once
// `linear_dashpot`: a linear spring-dashpot with its damping set by a coefficient of restitution
// e (LIGGGHTS `model hooke`, YADE's linear law with viscous damping), and a linear tangential
// spring with Coulomb friction (tangential_spring.hpp).
//
// Normal: the spring is the seed law's, k = c V^i V^j with c = 9 Ccon / (pi delta^5) (the mean
// of the two sides' c, so the pair is equal and opposite), so e = 1 and mu = 0 give the seed
// law's point-pair force. Against a mesh wall the point meets the wall as it would meet its own
// image: k = c (V^i)^2, m* = m^i (the wall does not give way).
//
// Closed forms. Two points of masses m_1, m_2 (m* = m_1 m_2 / (m_1 + m_2)) meeting at v_0 obey,
// while delta > 0,
//
//   m* delta'' + gamma delta' + k delta = 0,   delta(0) = 0,  delta'(0) = v_0.
//
// With omega_0 = sqrt(k / m*), zeta = gamma / (2 sqrt(k m*)) < 1, omega_d = omega_0 sqrt(1 -
// zeta^2):
//
//   delta(t) = v_0 / omega_d exp(-zeta omega_0 t) sin(omega_d t),
//
// which returns to zero at t_c = pi / omega_d (the contact duration), where
// delta'(t_c) = -v_0 exp(-zeta omega_0 t_c). So the coefficient of restitution is
//
//   e = exp(-zeta pi / sqrt(1 - zeta^2)),   i.e.   zeta = -ln e / sqrt(pi^2 + ln^2 e),
//
// independent of k and m*: gamma = 2 zeta sqrt(k m*) is what the law uses. The normal force
// k delta + gamma delta' turns attractive just before separation (delta' < 0); the law keeps it
// (that is what makes the closed form exact), friction sees only max(F_n, 0). Elastic energy
// k delta^2 / 2; the dashpot dissipates gamma v_n^2 per unit time.
//
// Tangential: k_t = `tangential_stiffness_ratio` x k (default 2/7: the tangential oscillation of
// a solid sphere, with its rotation, then has the normal one's period), no tangential dashpot.
//
// Keys: restitution (e, required), friction (mu, default 0), tangential_stiffness_ratio.
#include <cmath>
#include <numbers>

namespace ckpd::linear_dashpot {

inline double damping_ratio(double restitution) {
  const double l = std::log(restitution);
  return -l / std::sqrt(std::numbers::pi * std::numbers::pi + l * l);
}

inline double contact_duration(double stiffness, double mass, double restitution) {
  const double zeta = damping_ratio(restitution);
  return std::numbers::pi / (std::sqrt(stiffness / mass) * std::sqrt(1 - zeta * zeta));
}

}  // namespace ckpd::linear_dashpot
