#include "bodies/bond_family.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace ckpd {

namespace {

// A uniform grid of cells of edge >= horizon over the points' bounding box: the neighbours of
// a point lie in its own and the 26 adjacent cells.
struct CellGrid {
  Vec3 origin;
  double cell = 0;
  std::array<std::int64_t, 3> count{1, 1, 1};
  std::vector<std::size_t> start;      // CSR over cells
  std::vector<std::uint32_t> members;  // point indices sorted by cell, then index

  std::array<std::int64_t, 3> cell_of(const Vec3& p) const {
    std::array<std::int64_t, 3> c{};
    for (int d = 0; d < 3; ++d) {
      c[d] = std::clamp<std::int64_t>(static_cast<std::int64_t>((p[d] - origin[d]) / cell), 0,
                                      count[d] - 1);
    }
    return c;
  }
  std::size_t linear(const std::array<std::int64_t, 3>& c) const {
    return static_cast<std::size_t>((c[2] * count[1] + c[1]) * count[0] + c[0]);
  }
};

CellGrid make_grid(const std::vector<Vec3>& X, double horizon) {
  CellGrid g;
  Vec3 lo = X.front(), hi = X.front();
  for (const Vec3& p : X) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  g.origin = lo;
  g.cell = horizon * (1 + 1e-9);
  // Cap the number of cells so that a tiny horizon in a huge box cannot exhaust memory; a
  // coarser grid is still correct, only slower.
  const double max_cells = std::max<double>(64.0, 4.0 * static_cast<double>(X.size()));
  for (;;) {
    double total = 1;
    for (int d = 0; d < 3; ++d) {
      g.count[d] =
          std::max<std::int64_t>(1, static_cast<std::int64_t>((hi[d] - lo[d]) / g.cell) + 1);
      total *= static_cast<double>(g.count[d]);
    }
    if (total <= max_cells) break;
    g.cell *= 2;
  }
  const std::size_t cells = static_cast<std::size_t>(g.count[0] * g.count[1] * g.count[2]);
  g.start.assign(cells + 1, 0);
  std::vector<std::size_t> cell_of_point(X.size());
  for (std::size_t i = 0; i < X.size(); ++i) {
    cell_of_point[i] = g.linear(g.cell_of(X[i]));
    ++g.start[cell_of_point[i] + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) g.start[c + 1] += g.start[c];
  g.members.resize(X.size());
  std::vector<std::size_t> fill(g.start.begin(), g.start.end() - 1);
  for (std::size_t i = 0; i < X.size(); ++i)
    g.members[fill[cell_of_point[i]]++] = static_cast<std::uint32_t>(i);
  return g;
}

}  // namespace

BondFamily build_bond_family(const std::vector<Vec3>& X, double horizon) {
  if (!(horizon > 0)) throw std::invalid_argument("horizon must be positive");
  if (X.size() >= std::numeric_limits<std::uint32_t>::max())
    throw std::invalid_argument("too many points for 32-bit indices: " + std::to_string(X.size()));
  for (std::size_t i = 0; i < X.size(); ++i) {
    if (!X[i].allFinite())
      throw std::invalid_argument("point " + std::to_string(i) + " has a non-finite position");
  }
  BondFamily family;
  family.offset.assign(X.size() + 1, 0);
  if (X.empty()) return family;

  const CellGrid grid = make_grid(X, horizon);
  const std::size_t n = X.size();
  // Two passes (count, then fill) keep the CSR arrays exactly sized.
  auto visit = [&](std::size_t i, auto&& emit) {
    const auto c = grid.cell_of(X[i]);
    for (std::int64_t dz = -1; dz <= 1; ++dz)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dx = -1; dx <= 1; ++dx) {
          const std::array<std::int64_t, 3> nc{c[0] + dx, c[1] + dy, c[2] + dz};
          bool inside = true;
          for (int d = 0; d < 3; ++d) inside &= nc[d] >= 0 && nc[d] < grid.count[d];
          if (!inside) continue;
          const std::size_t cell = grid.linear(nc);
          for (std::size_t m = grid.start[cell]; m < grid.start[cell + 1]; ++m) {
            const std::uint32_t j = grid.members[m];
            if (j != i && within_horizon(X[j] - X[i], horizon)) emit(j);
          }
        }
  };

#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t count = 0;
    visit(i, [&](std::uint32_t) { ++count; });
    family.offset[i + 1] = count;
  }
  for (std::size_t i = 0; i < n; ++i) family.offset[i + 1] += family.offset[i];
  family.neighbour.resize(family.offset[n]);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t k = family.offset[i];
    visit(i, [&](std::uint32_t j) { family.neighbour[k++] = j; });
    std::sort(family.neighbour.begin() + static_cast<std::ptrdiff_t>(family.offset[i]),
              family.neighbour.begin() + static_cast<std::ptrdiff_t>(k));
  }
  return family;
}

}  // namespace ckpd
