#pragma once
// Bonds {i, j} of point i's upper family, each once: d1 is the same from both ends, and
// dx^ji = -dx^ij exactly, so j gets minus i's term weighted by its own dV1^j.
#include "bodies/symmetric/centre.hpp"

namespace ckpd::symmetric {

template <class Model, bool kEnergy, bool kStencil>
inline void bond_loop(const Context<Model>& ctx, SymmetricKernelThread& t, Centre& centre) {
  const Body& body = *ctx.body;
  const LatticeStencil* st = ctx.stencil;
  const std::size_t W = t.words;
  const std::uint64_t* own = t.own.data();
  const std::uint32_t* __restrict up = t.up.data();
  const double* __restrict Rx = t.Rx.data();
  const double* __restrict Ry = t.Ry.data();
  const double* __restrict Rz = t.Rz.data();
  const double* __restrict rx = t.rx.data();
  const double* __restrict ry = t.ry.data();
  const double* __restrict rz = t.rz.data();
  double* __restrict fx = t.fx.data();
  double* __restrict fy = t.fy.data();
  double* __restrict fz = t.fz.data();
  double* __restrict slot_w = t.w.data();
  const double dv1i = body.dv1[centre.index];
  double fix = 0, fiy = 0, fiz = 0, wi = 0;
  std::uint64_t bonds = 0;
  // Far-field masking: a linear centre's bonds to linear points are left out.
  const std::uint64_t* exact_slots = t.linear_centre ? t.exact_slots.data() : nullptr;
  for (std::size_t wd = 0; wd < W; ++wd) {
    const std::uint64_t mask = exact_slots != nullptr ? exact_slots[wd] : ~std::uint64_t{0};
    for (std::uint64_t bits = own[wd] & mask; bits; bits &= bits - 1) {
      const std::size_t a = wd * 64 + static_cast<std::size_t>(std::countr_zero(bits));
      double L, inv_L;
      if constexpr (kStencil) {
        L = st->length[a];
        inv_L = st->inv_length[a];
      } else {
        L = std::sqrt(Rx[a] * Rx[a] + Ry[a] * Ry[a] + Rz[a] * Rz[a]);
        inv_L = 1 / L;
      }
      const double l = std::sqrt(rx[a] * rx[a] + ry[a] * ry[a] + rz[a] * rz[a]);
      const double k = ctx.model.bond_coefficient(BondMeasure{L, inv_L}, l);
      const double dv1j = body.dv1[up[a]];
      fix += k * dv1i * rx[a];
      fiy += k * dv1i * ry[a];
      fiz += k * dv1i * rz[a];
      fx[a] -= k * dv1j * rx[a];
      fy[a] -= k * dv1j * ry[a];
      fz[a] -= k * dv1j * rz[a];
      if constexpr (kEnergy) {
        // psi1 / 2 per end: W = W1 / 2.
        const double e = 0.5 * ctx.model.bond_energy(L, ctx.model.bond_stretch(L, l));
        wi += e * dv1i;
        slot_w[a] += e * dv1j;
      }
      ++bonds;
    }
  }
  centre.fx += fix;
  centre.fy += fiy;
  centre.fz += fiz;
  if constexpr (kEnergy) centre.w += wi;
  centre.count.bonds += bonds;
}

}  // namespace ckpd::symmetric
