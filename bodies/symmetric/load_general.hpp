#pragma once
// The general path's load of point i's upper family (any point set).
#include "bodies/symmetric/context.hpp"

namespace ckpd::symmetric {

// Loads point i's upper family into the scratch: offsets, intact bits, per-slot weights and,
// with `rows`, the adjacency between slots. Adjacency comes from the CSR rows, not from
// distances: slot b is in row a iff up[b] is in H1(up[a]), found by merging the two sorted
// index lists, and the bond's intact flag is read at the matching CSR position of up[a]'s row.
// Returns m (0: nothing to do).
template <class Model>
inline std::size_t load_upper_family(const Context<Model>& ctx, std::size_t i,
                                     SymmetricKernelThread& t, bool rows) {
  const std::uint32_t* nb = ctx.neighbour;
  const std::size_t begin = ctx.offset[i], end = ctx.offset[i + 1];
  const std::size_t first = static_cast<std::size_t>(
      std::upper_bound(nb + begin, nb + end, static_cast<std::uint32_t>(i)) - nb);
  const std::size_t m = end - first;
  t.m = m;
  if (m == 0) return 0;
  const std::size_t W = (m + 63) / 64;
  t.words = W;
  t.reserve(m, W);
  const Vec3 Xi = ctx.X[i];
  const Vec3 ui = ctx.u ? ctx.u[i] : Vec3::Zero();
  std::fill_n(t.own.begin(), W, 0);
  std::fill_n(t.present.begin(), W, ~std::uint64_t{0});
  if (m % 64) t.present[W - 1] = (std::uint64_t{1} << (m % 64)) - 1;
  t.count = m;
  t.intact_is_adjacency = false;
  bool failed_near = ctx.row_failed != nullptr && ctx.row_failed[i] != 0;
  for (std::size_t a = 0; a < m; ++a) {
    const std::uint32_t j = nb[first + a];
    t.up[a] = j;
    t.list[a] = static_cast<std::uint32_t>(a);
    fill_slot(ctx, t, a, j, Xi, ui);
    if (ctx.bond_intact(first + a)) set_bit(t.own.data(), a);
    if (ctx.row_failed != nullptr) failed_near = failed_near || ctx.row_failed[j] != 0;
  }
  mark_exact_slots(ctx, t, i);
  if (!rows) return m;
  // The adjacency rows: copied from the body's table where it has one, else gathered from the
  // CSR rows. No failed bond in the rows of i and its upper neighbours: the intact rows are the
  // adjacency (as on the stencil path), not built.
  if (ctx.upper_rows != nullptr) {
    std::copy_n(&ctx.upper_rows->words[ctx.upper_rows->start[i]], m * W, t.adj.data());
    if (failed_near) build_csr_rows(ctx, t, nullptr);
  } else {
    build_csr_rows(ctx, t, t.adj.data(), failed_near);
  }
  t.intact_is_adjacency = !failed_near;
  return m;
}

}  // namespace ckpd::symmetric
