#include "bodies/upper_rows.hpp"

#include <omp.h>

#include <algorithm>

#include "bodies/body.hpp"
#include "bodies/symmetric/context.hpp"

namespace ckpd {

namespace {

// Point i's upper slots: m and the words per row.
std::pair<std::size_t, std::size_t> upper_shape(const BondFamily& family, std::size_t i) {
  const std::uint32_t* nb = family.neighbour.data();
  const std::size_t begin = family.offset[i], end = family.offset[i + 1];
  const std::size_t first = static_cast<std::size_t>(
      std::upper_bound(nb + begin, nb + end, static_cast<std::uint32_t>(i)) - nb);
  const std::size_t m = end - first;
  return {m, (m + 63) / 64};
}

}  // namespace

std::size_t upper_rows_bytes(const BondFamily& family) {
  const std::size_t n = family.offset.empty() ? 0 : family.offset.size() - 1;
  std::size_t words = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto [m, W] = upper_shape(family, i);
    words += m * W;
  }
  return words * sizeof(std::uint64_t) + (n + 1) * sizeof(std::size_t);
}

std::shared_ptr<const UpperRows> build_upper_rows(const Body& body, std::size_t limit) {
  if (upper_rows_bytes(body.family) > limit) return nullptr;
  auto rows = std::make_shared<UpperRows>();
  const std::size_t n = body.size();
  rows->bonds = body.family.neighbour.size();
  rows->start.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const auto [m, W] = upper_shape(body.family, i);
    rows->start[i + 1] = rows->start[i] + m * W;
  }
  rows->words.assign(rows->start[n], 0);
  // The rows as the general path's load gathers them (symmetric::build_csr_rows), so that the
  // kernel's result does not depend on which it reads.
  const symmetric::ContextBase ctx = symmetric::make_context_base(body);
#pragma omp parallel
  {
    SymmetricKernelThread t;
#pragma omp for schedule(dynamic, 256)
    for (std::size_t i = 0; i < n; ++i) {
      const auto [m, W] = upper_shape(body.family, i);
      if (m == 0) continue;
      t.reserve(m, W);
      t.words = W;
      t.count = m;
      const std::size_t first = body.family.offset[i + 1] - m;
      for (std::size_t a = 0; a < m; ++a) {
        t.up[a] = body.family.neighbour[first + a];
        t.list[a] = static_cast<std::uint32_t>(a);
      }
      symmetric::build_csr_rows(ctx, t, &rows->words[rows->start[i]], false);
    }
  }
  return rows;
}

}  // namespace ckpd
