#pragma once
// The lattice stencil path's load of point i's upper family (lattice_stencil.hpp).
#include "bodies/bit_move.hpp"
#include "bodies/symmetric/context.hpp"

namespace ckpd::symmetric {

// The intact rows of a centre near damage: row a is the adjacency row less the bonds of up[a]
// that failed, read from up[a]'s failed upper bonds in its own slots (failed_upper, which
// compute_of builds once per row and step) moved to the centre's slots: those in the stencil's
// sum_inside row a, in order, to the slots of its adjacency row a (PEXT, PDEP). Equal bit for
// bit to build_csr_rows' rows, which scan up[a]'s flags again at every centre and look each
// failed bond's slot up.
inline void intact_rows_stencil(const ContextBase& ctx, SymmetricKernelThread& t) {
  const LatticeStencil& st = *ctx.stencil;
  const std::size_t W = t.words;
  for (std::size_t n = 0; n < t.count; ++n) {
    const std::size_t a = t.list[n];
    const std::uint32_t j = t.up[a];
    std::uint64_t* irow = &t.adj_intact[a * W];
    const std::uint8_t state = ctx.row_failed[j];
    if (state == ContextBase::kAllFailed) {
      std::fill_n(irow, W, 0);
      continue;
    }
    const std::uint64_t* adj = &t.adj[a * W];
    if (state == 0) {
      std::copy_n(adj, W, irow);
      continue;
    }
    move_bits(ctx.failed_upper + std::size_t{j} * W, &st.sum_inside[a * W], &st.adjacency[a * W], W,
              irow);
    for (std::size_t w = 0; w < W; ++w) irow[w] = adj[w] & ~irow[w];
  }
}

// The stencil path's load: slots are the stencil's upper offsets; each neighbour j > i of i
// goes to the slot of its lattice offset, with the same offsets, flags and weights as
// load_upper_family. Adjacency rows are the stencil's rows restricted to the present slots;
// intact rows are built only when a bond near i has failed (intact_rows_stencil). Returns the
// number of present slots (0: nothing to do).
template <class Model>
inline std::size_t load_upper_family_stencil(const Context<Model>& ctx, std::size_t i,
                                             SymmetricKernelThread& t, bool rows) {
  const LatticeStencil& st = *ctx.stencil;
  const std::uint32_t* nb = ctx.neighbour;
  const std::size_t begin = ctx.offset[i], end = ctx.offset[i + 1];
  const std::size_t first = static_cast<std::size_t>(
      std::upper_bound(nb + begin, nb + end, static_cast<std::uint32_t>(i)) - nb);
  const std::size_t count = end - first;
  t.count = count;
  if (count == 0) return 0;
  const std::size_t M = st.slots, W = st.words;
  t.m = M;
  t.words = W;
  t.reserve(M, W);
  const Vec3 Xi = ctx.X[i];
  const Vec3 ui = ctx.u ? ctx.u[i] : Vec3::Zero();
  std::fill_n(t.own.begin(), W, 0);
  std::fill_n(t.present.begin(), W, 0);
  bool failed_near = ctx.row_failed != nullptr && ctx.row_failed[i] != 0;
  // The slots first (independent look-ups), then the bit rows (in registers for one word: a
  // read-modify-write of the same word per slot would chain the iterations), then the slots'
  // contents.
  std::uint32_t* __restrict list = t.list.data();
  for (std::size_t n = 0; n < count; ++n)
    list[n] = static_cast<std::uint32_t>(st.slot(i, nb[first + n]));
  if (W == 1) {
    std::uint64_t present = 0, own = 0;
    for (std::size_t n = 0; n < count; ++n) {
      const std::uint64_t b = std::uint64_t{1} << list[n];
      present |= b;
      own |= ctx.bond_intact(first + n) ? b : 0;
    }
    t.present[0] = present;
    t.own[0] = own;
  } else {
    for (std::size_t n = 0; n < count; ++n) {
      set_bit(t.present.data(), list[n]);
      if (ctx.bond_intact(first + n)) set_bit(t.own.data(), list[n]);
    }
  }
  for (std::size_t n = 0; n < count; ++n) {
    const std::uint32_t j = nb[first + n];
    const std::size_t a = list[n];
    t.up[a] = j;
    fill_slot(ctx, t, a, j, Xi, ui);
    if (ctx.row_failed != nullptr) failed_near = failed_near || ctx.row_failed[j] != 0;
  }
  mark_exact_slots(ctx, t, i);
  if (!rows) return count;
  const std::uint64_t* present = t.present.data();
  for (std::size_t n = 0; n < count; ++n) {
    const std::size_t a = t.list[n];
    const std::uint64_t* srow = &st.adjacency[a * W];
    std::uint64_t* row = &t.adj[a * W];
    for (std::size_t w = 0; w < W; ++w) row[w] = srow[w] & present[w];
  }
  t.intact_is_adjacency = !failed_near;
  if (failed_near) intact_rows_stencil(ctx, t);  // failed_near: compute_of set failed_upper
  return count;
}

}  // namespace ckpd::symmetric
