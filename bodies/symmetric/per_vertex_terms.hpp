#pragma once
// The reference's own term for centre c of a triangle (other vertices o1 < o2) or tetrahedron
// (o1 < o2 < o3): the model's per-set term seen from c (the same function the reference kernel
// evaluates, point_kernel.hpp), on offsets formed with FamilyScratch::load's operations. The
// path for ill-conditioned sets, whose shared-geometry evaluation would differ from the
// reference by more than the tests' 1e-12 (see kWellConditioned). Returns false when c sees the
// set as degenerate. `w` is the term's share of W = W2/3 (W3/4).
#include "bodies/symmetric/context.hpp"

namespace ckpd::symmetric {

template <class Model>
bool reference_triangle_term(const Context<Model>& ctx, std::uint32_t c, std::uint32_t o1,
                             std::uint32_t o2, Vec3& force, double& w, bool& inverted) {
  const Vec3 Xc = ctx.X[c];
  const Vec3 P = ctx.X[o1] - Xc, Q = ctx.X[o2] - Xc;
  const Vec3 uc = ctx.u ? ctx.u[c] : Vec3::Zero();
  const Vec3 p = ctx.u ? Vec3(P + (ctx.u[o1] - uc)) : P;
  const Vec3 q = ctx.u ? Vec3(Q + (ctx.u[o2] - uc)) : Q;
  const SetTerm<3> t = ctx.model.triangle_term(P, Q, p, q, ctx.degenerate);
  if (t.degenerate) return false;
  inverted = t.inverted;
  const double k = ctx.model.triangle_force_weight(ctx.body->dv2[c]);
  force = k * t.force[0];
  w = k * t.energy / 3;
  return true;
}

template <class Model>
bool reference_tetrahedron_term(const Context<Model>& ctx, std::uint32_t c, std::uint32_t o1,
                                std::uint32_t o2, std::uint32_t o3, Vec3& force, double& w,
                                bool& inverted) {
  const Vec3 Xc = ctx.X[c];
  const Vec3 P = ctx.X[o1] - Xc, Q = ctx.X[o2] - Xc, R = ctx.X[o3] - Xc;
  const Vec3 uc = ctx.u ? ctx.u[c] : Vec3::Zero();
  const Vec3 p = ctx.u ? Vec3(P + (ctx.u[o1] - uc)) : P;
  const Vec3 q = ctx.u ? Vec3(Q + (ctx.u[o2] - uc)) : Q;
  const Vec3 r = ctx.u ? Vec3(R + (ctx.u[o3] - uc)) : R;
  const SetTerm<4> t = ctx.model.tetrahedron_term(P, Q, R, p, q, r, ctx.degenerate);
  if (t.degenerate) return false;
  inverted = t.inverted;
  const double k = ctx.model.tetrahedron_force_weight(ctx.body->dv3[c]);
  force = k * t.force[0];
  w = k * t.energy / 4;
  return true;
}

}  // namespace ckpd::symmetric
