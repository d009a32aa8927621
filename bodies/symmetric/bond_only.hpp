#pragma once
// Point i of the symmetric kernel for a body with bonds only (no two- or three-neighbour sets,
// no lattice stencil, no far field, no replicated rank share): its bonds {i, j}, j > i, straight
// from the CSR row, with L and 1/L from the body's table (upper_bonds.hpp). Same arithmetic, in
// the same order, as load_upper_family + bond_loop (+ bond_loop_conservative) and the flush of
// process_point, so the forces and energies are those of the general path bit for bit; without
// its per-slot bookkeeping (bit rows, per-slot weights, accumulators) and with the square root
// and division of l in a loop the compiler vectorises.
//
// With kFail, the damage step of fail_bonds_only (bond_failure.hpp) happens in the same pass:
// a bond that breaks now (breaks_now, the same test at the same displacement) is failed from
// both ends and left out of the forces, and both ends are marked for the booking
// (book_fused_failures), which sums the same per-row terms in the same order as
// fail_bonds_only: same failed bonds, same dissipated energy, bit for bit.
//
// On a rank's restriction (bodies/sub_body.hpp: owned_centres = booked_points = the owned points)
// the rank computes the bonds of its owned points' rows. A bond {g, o} from a ghost g < o to an
// owned o is another rank's to compute, but o's flags must follow it (o's damage, its family in
// the gather, self-contact), so ghost_bond_failures fails it here too, by the same test at the
// same positions as g's owner does: the flags of every owned point's family are those of
// fail_bonds_only on the restriction, which the separate pass gave before.
#include <atomic>
#include <cmath>

#include "bodies/bond_failure.hpp"
#include "bodies/symmetric/context.hpp"

namespace ckpd::symmetric {

// The bonds failing in one fused evaluation: one flag per stored bond and per point, all zero
// between evaluations (book_fused_failures clears what the kernel set).
struct FusedFailure {
  bool protect = false;             // the body has no-failure points
  std::uint8_t* failing = nullptr;  // per CSR entry: fails now
  std::uint8_t* touched = nullptr;  // per point: holds a bond that fails now
};

// Whether a body takes this path (and compute_of calls bond_only_point for every centre).
template <class Model>
bool bond_only_path(const Context<Model>& ctx, const SymmetricKernelWorkspace& workspace) {
  const Body& body = *ctx.body;
  const bool sets = (Model::kTriangles && ctx.pairs) || (Model::kTetrahedra && ctx.triples);
  // A replicated share (owned_centres without booked_points: every rank keeps every flag) needs
  // the separate failure pass over all bonds; a restriction books its owned points only.
  const bool share = !body.owned_centres.empty();
  const bool restriction = share && body.booked_points == body.owned_centres;
  return !sets && ctx.stencil == nullptr && workspace.skip_centre == nullptr &&
         workspace.exact_point == nullptr && (!share || restriction) &&
         body.upper_bonds != nullptr && body.upper_bonds->matches(body.family);
}

// Bond {i, j} (j > i, stored at k in i's row) fails now: from both ends, both marked for the
// booking. The reverse entry (i in j's row, below j) is this bond's alone, so no other thread
// touches it.
template <class Model>
inline void fail_from_both_ends(const Context<Model>& ctx, std::size_t i, std::size_t k,
                                std::uint32_t j, const FusedFailure& fused) {
  const UpperBonds& table = *ctx.body->upper_bonds;
  const std::uint32_t* row = ctx.neighbour + ctx.offset[j];
  const std::size_t back =
      ctx.offset[j] + static_cast<std::size_t>(std::lower_bound(row, ctx.neighbour + table.first[j],
                                                                static_cast<std::uint32_t>(i)) -
                                               row);
  Body& body = const_cast<Body&>(*ctx.body);
  body.bond_intact[k] = 0;
  body.bond_intact[back] = 0;
  fused.failing[k] = 1;
  fused.failing[back] = 1;
  std::atomic_ref<std::uint8_t>(fused.touched[i]).store(1, std::memory_order_relaxed);
  std::atomic_ref<std::uint8_t>(fused.touched[j]).store(1, std::memory_order_relaxed);
}

// A ghost i of a rank's restriction: its bonds to owned points above it that break now, failed
// from both ends and marked for the booking, as bond_only_point<kFail> does for an owned i (no
// forces: the ghost's owner computes them). `failed` counts them.
template <class Model>
inline void ghost_bond_failures(const Context<Model>& ctx, std::size_t i, const FusedFailure& fused,
                                std::size_t& failed) {
  const Body& body = *ctx.body;
  const UpperBonds& table = *body.upper_bonds;
  const std::size_t end = ctx.offset[i + 1];
  for (std::size_t k = table.first[i]; k < end; ++k) {
    const std::uint32_t j = ctx.neighbour[k];
    if (!body.owned_centres[j] || !ctx.bond_intact(k)) continue;
    if (!bond_failure_detail::breaks_now(ctx.model, body, fused.protect, i, k)) continue;
    fail_from_both_ends(ctx, i, k, j, fused);
    ++failed;
  }
}

template <class Model, bool kEnergy, bool kFail>
inline void bond_only_point(const Context<Model>& ctx, std::size_t i, SymmetricKernelThread& t,
                            const FusedFailure& fused, std::size_t& failed) {
  const Body& body = *ctx.body;
  const UpperBonds& table = *body.upper_bonds;
  const std::size_t first = table.first[i], end = ctx.offset[i + 1];
  if (first == end) return;
  const std::size_t m = end - first;
  t.reserve(m, (m + 63) / 64);
  const std::uint32_t* __restrict nb = ctx.neighbour + first;
  const double* __restrict L = table.length.data() + table.start[i];
  const double* __restrict inv_L = table.inverse_length.data() + table.start[i];
  double* __restrict rx = t.rx.data();
  double* __restrict ry = t.ry.data();
  double* __restrict rz = t.rz.data();
  double* __restrict coefficient = t.fx.data();
  double* __restrict energy = t.w.data();
  double* __restrict screen = t.fy.data();
  constexpr bool kConservative = conservative_form<Model>();
  double* __restrict vol = t.vol.data();
  double* __restrict inv_vol = t.inv_vol.data();
  // The current offsets, as fill_slot forms them.
  const Vec3 Xi = ctx.X[i];
  const Vec3 ui = ctx.u ? ctx.u[i] : Vec3::Zero();
  for (std::size_t a = 0; a < m; ++a) {
    const std::uint32_t j = nb[a];
    const Vec3 R = ctx.X[j] - Xi;
    const Vec3 r = ctx.u ? Vec3(R + (ctx.u[j] - ui)) : R;
    rx[a] = r.x();
    ry[a] = r.y();
    rz[a] = r.z();
    if constexpr (kConservative) vol[a] = body.volume[j];
  }
  // Per bond: l, the force coefficient, the energy, and (kFail) a screen for the failure test. A
  // loop without branches or stores the compiler cannot separate (the model is a local copy):
  // vectorised.
  const Model model = ctx.model;
  for (std::size_t a = 0; a < m; ++a) {
    const double l = std::sqrt(rx[a] * rx[a] + ry[a] * ry[a] + rz[a] * rz[a]);
    coefficient[a] = model.bond_coefficient(BondMeasure{L[a], inv_L[a]}, l);
    if constexpr (kEnergy) energy[a] = 0.5 * model.bond_energy(L[a], model.bond_stretch(L[a], l));
    if constexpr (kFail) {
      // l/L - 1 is within 1e-12 of the exact stretch's rounding: every bond the exact test
      // (breaks_now) fails passes this screen.
      const double s = l * inv_L[a] - 1;
      screen[a] = model.bond_fails(s + 1e-12 * (1 + std::abs(s))) ? 1.0 : 0.0;
    }
    if constexpr (kConservative) inv_vol[a] = 1 / vol[a];
  }
  const double dv1i = body.dv1[i];
  [[maybe_unused]] const double Vi = body.volume[i], xi = Vi * dv1i, inv_vi = 1 / Vi;
  double fix = 0, fiy = 0, fiz = 0, wi = 0;
  std::uint64_t bonds = 0;
  Vec3* __restrict force = t.force.data();
  double* __restrict point_energy = t.energy.data();
  for (std::size_t a = 0; a < m; ++a) {
    const std::size_t k = first + a;
    if (!ctx.bond_intact(k)) continue;
    const std::uint32_t j = nb[a];
    if constexpr (kFail) {
      if (screen[a] != 0 && bond_failure_detail::breaks_now(model, body, fused.protect, i, k)) {
        fail_from_both_ends(ctx, i, k, j, fused);
        ++failed;
        continue;
      }
    }
    const double c = coefficient[a];
    const double dv1j = body.dv1[j];
    if constexpr (kConservative) {
      const double K = 0.5 * (xi + vol[a] * dv1j);  // both ends hold the bond, both active
      const double ki = c * (K * inv_vi), kj = c * (K * inv_vol[a]);
      fix += ki * rx[a];
      fiy += ki * ry[a];
      fiz += ki * rz[a];
      force[j].x() -= kj * rx[a];
      force[j].y() -= kj * ry[a];
      force[j].z() -= kj * rz[a];
    } else {
      fix += c * dv1i * rx[a];
      fiy += c * dv1i * ry[a];
      fiz += c * dv1i * rz[a];
      force[j].x() -= c * dv1j * rx[a];
      force[j].y() -= c * dv1j * ry[a];
      force[j].z() -= c * dv1j * rz[a];
    }
    if constexpr (kEnergy) {
      wi += energy[a] * dv1i;
      point_energy[j] += energy[a] * dv1j;
    }
    ++bonds;
  }
  force[i] += Vec3(fix, fiy, fiz);
  if constexpr (kEnergy) point_energy[i] += wi;
  t.stats.bonds += bonds;
}

// After a fused evaluation: the energy the failed bonds took, booked as fail_bonds_only books
// it (per point, its row's failing entries in CSR order, then the points in order), and the
// flags cleared for the next one.
template <class Model>
double book_fused_failures(const Model& model, const Body& body, double half_drift,
                           const FusedFailure& fused) {
  double dissipated = 0;
  const std::size_t n = body.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (!fused.touched[i]) continue;
    fused.touched[i] = 0;
    if (!body.books(i)) {  // a ghost of a restriction: its owner books its row
      for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k)
        fused.failing[k] = 0;
      continue;
    }
    dissipated +=
        bond_failure_detail::failing_row_energy(model, body, i, half_drift, [&](std::size_t k) {
          if (!fused.failing[k]) return false;
          fused.failing[k] = 0;
          return true;
        });
  }
  return dissipated;
}

}  // namespace ckpd::symmetric
