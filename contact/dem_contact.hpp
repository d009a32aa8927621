#pragma once
// One DEM contact (dem_law.hpp) evaluated: the law's normal force with its dashpot, then the
// tangential spring (tangential_spring.hpp) held to Coulomb's limit. Shared by point pairs
// (contact_manager.cpp) and points against mesh walls (mesh_wall_contact.cpp).
#include <algorithm>

#include "contact/dem_law.hpp"
#include "contact/tangential_spring.hpp"

namespace ckpd {

struct DemContact {
  Vec3 force = Vec3::Zero();   // N, on side a
  Vec3 spring = Vec3::Zero();  // the tangential history after this step
  double energy = 0;           // J: elastic normal energy plus the spring's k_t |xi|^2 / 2
  double damping_power = 0;    // W: gamma v_n^2, dissipated by the dashpot
  double slip_work = 0;        // J: dissipated by sliding in this step
};

// `normal`: unit, from b towards a; `velocity`: of a's material relative to b's at the contact
// point; `previous`: the spring of the last step (zero for a new contact).
inline DemContact dem_contact(const DemLaw& law, double overlap, const Vec3& normal,
                              const Vec3& velocity, const LawPoint& a, const LawPoint& b, bool wall,
                              const Vec3& previous, double dt) {
  const NormalResponse r = law.normal(overlap, a, b, wall);
  const double vn = velocity.dot(normal);
  const double fn = r.force - r.damping * vn;
  DemContact c;
  c.force = fn * normal;
  c.energy = r.energy;
  c.damping_power = r.damping * vn * vn;
  if (law.friction > 0) {
    const TangentialStep t = tangential_step(previous, normal, velocity, dt, r.tangential_stiffness,
                                             law.friction * std::max(fn, 0.0));
    c.force += t.force;
    c.spring = t.spring;
    c.energy += 0.5 * r.tangential_stiffness * t.spring.squaredNorm();
    c.slip_work = t.slip_work;
  }
  return c;
}

}  // namespace ckpd
