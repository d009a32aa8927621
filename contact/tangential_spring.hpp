#pragma once
// The tangential history of one contact (Cundall and Strack 1979, as YADE's
// Law2_ScGeom_FrictPhys_CundallStrack and LIGGGHTS' `tangential history`): a spring xi that
// accumulates the relative tangential displacement of the two sides at the contact point,
// F_t = -k_t xi, held to Coulomb's limit |F_t| <= mu max(F_n, 0).
//
// Every step, before the increment, the spring of the last step is turned into the current
// contact plane (its normal component removed, its length kept), so a contact that rolls or
// turns keeps its stored force tangential. When the trial force exceeds the limit the spring is
// cut back to it (gross sliding); the work of friction over the slip is mu F_n times the length
// cut, which is what the step dissipates (the elastic energy of the cut part, k_t |cut|^2 / 2,
// is of second order in the slip and is the spring energy given up). A contact that opens loses
// its spring (the caller drops the history).
//
// Every operation is odd in (xi, n, v): the other side of the pair, computing with the negated
// inputs, gets the exactly negated spring and force, so both ends agree bit for bit.
#include "bodies/vec.hpp"

namespace ckpd {

struct TangentialStep {
  Vec3 spring = Vec3::Zero();  // xi after the step
  Vec3 force = Vec3::Zero();   // on the side whose relative velocity `velocity` is
  double slip_work = 0;        // J dissipated by sliding in this step
};

// `previous`: xi of the last step (zero for a new contact); `normal`: unit, current;
// `velocity`: relative velocity of this side against the other at the contact point;
// `limit`: mu max(F_n, 0).
inline TangentialStep tangential_step(const Vec3& previous, const Vec3& normal,
                                      const Vec3& velocity, double dt, double stiffness,
                                      double limit) {
  TangentialStep s;
  Vec3 xi = previous - previous.dot(normal) * normal;
  const double kept = xi.norm();
  if (kept > 0) xi *= previous.norm() / kept;
  xi += dt * (velocity - velocity.dot(normal) * normal);
  const double trial = stiffness * xi.norm();
  if (trial > limit) {
    const Vec3 cut = trial > 0 ? Vec3((limit / trial) * xi) : Vec3::Zero();
    s.slip_work = limit * (xi - cut).norm();
    xi = cut;
  }
  s.spring = xi;
  s.force = -stiffness * xi;
  return s;
}

}  // namespace ckpd
