#include "src/engine/decomposition.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

namespace ckpd {

namespace {

// Operation counts per interaction (docs/PERFORMANCE.md, "Floating-point operations per
// interaction", general path).
constexpr double kBondOps = 23, kTriangleOps = 70, kTetrahedronOps = 26;

struct Item {
  Vec3 x;
  double work;
  std::uint32_t body, point;
};

// Assigns items[begin, end) to ranks [first, first + count), cutting recursively.
void bisect(std::vector<Item>& items, std::size_t begin, std::size_t end, int first, int count,
            Decomposition& d) {
  if (count == 1) {
    for (std::size_t k = begin; k < end; ++k) d.owner[items[k].body][items[k].point] = first;
    return;
  }
  Vec3 lo = items[begin].x, hi = items[begin].x;
  for (std::size_t k = begin; k < end; ++k) {
    lo = lo.cwiseMin(items[k].x);
    hi = hi.cwiseMax(items[k].x);
  }
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  const auto first_item = items.begin() + static_cast<std::ptrdiff_t>(begin);
  const auto last_item = items.begin() + static_cast<std::ptrdiff_t>(end);
  std::sort(first_item, last_item, [axis](const Item& a, const Item& b) {
    if (a.x[axis] != b.x[axis]) return a.x[axis] < b.x[axis];
    if (a.body != b.body) return a.body < b.body;
    return a.point < b.point;
  });
  const int left = count / 2;
  double total = 0;
  for (std::size_t k = begin; k < end; ++k) total += items[k].work;
  const double target = total * left / count;
  // The cut nearest to the target work that leaves each side at least as many points as ranks.
  const std::size_t min_cut = begin + static_cast<std::size_t>(left);
  const std::size_t max_cut = end - static_cast<std::size_t>(count - left);
  std::size_t cut = min_cut;
  double prefix = 0;
  for (std::size_t k = begin; k < min_cut; ++k) prefix += items[k].work;
  double best = std::abs(prefix - target);
  for (std::size_t k = min_cut; k < max_cut; ++k) {
    prefix += items[k].work;
    const double miss = std::abs(prefix - target);
    if (miss < best) {
      best = miss;
      cut = k + 1;
    }
  }
  bisect(items, begin, cut, first, left, d);
  bisect(items, cut, end, first + left, count - left, d);
}

}  // namespace

double point_work(const Body& body, std::size_t i) {
  const double bonds = static_cast<double>(body.family.family_size(i)) / 2;
  const double triangles = body.n2.empty() ? 0.0 : body.n2[i] / 2.0 / 3.0;
  const double tetrahedra = body.n3.empty() ? 0.0 : body.n3[i] / 6.0 / 4.0;
  return kBondOps * bonds + kTriangleOps * triangles + kTetrahedronOps * tetrahedra;
}

double Decomposition::imbalance() const {
  double most = 0, sum = 0;
  for (const RankShare& s : share) {
    most = std::max(most, s.work);
    sum += s.work;
  }
  return sum > 0 ? most * static_cast<double>(share.size()) / sum : 1.0;
}

Decomposition decompose(const std::vector<const Body*>& bodies, const std::vector<bool>& rigid,
                        int ranks) {
  if (ranks < 1) throw std::invalid_argument("the rank count must be at least 1");
  Decomposition d;
  d.ranks = ranks;
  d.owner.resize(bodies.size());
  d.share.assign(static_cast<std::size_t>(ranks), RankShare{});
  std::vector<Item> items;
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const Body& body = *bodies[b];
    d.owner[b].assign(body.size(), -1);
    if (rigid[b]) continue;
    for (std::size_t i = 0; i < body.size(); ++i)
      items.push_back({body.reference_position[i], point_work(body, i),
                       static_cast<std::uint32_t>(b), static_cast<std::uint32_t>(i)});
  }
  if (items.size() < static_cast<std::size_t>(ranks))
    throw std::invalid_argument("the scene has " + std::to_string(items.size()) +
                                " deformable points, fewer than the " + std::to_string(ranks) +
                                " ranks: each rank needs at least one");
  bisect(items, 0, items.size(), 0, ranks, d);
  // Owned counts, work and halos. A ghost is marked once per rank with the rank's stamp.
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    if (rigid[b]) continue;
    const Body& body = *bodies[b];
    const std::vector<int>& own = d.owner[b];
    // The body's points grouped by owner (counting sort), so that each rank's halo is found
    // with one pass over its own points' families.
    std::vector<std::size_t> start(static_cast<std::size_t>(ranks) + 1, 0);
    for (const int r : own) ++start[static_cast<std::size_t>(r) + 1];
    std::partial_sum(start.begin(), start.end(), start.begin());
    std::vector<std::uint32_t> by_rank(body.size());
    std::vector<std::size_t> next(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < body.size(); ++i)
      by_rank[next[static_cast<std::size_t>(own[i])]++] = static_cast<std::uint32_t>(i);
    std::vector<int> stamp(body.size(), -1);  // the last rank that counted the point as a ghost
    for (int r = 0; r < ranks; ++r) {
      RankShare& s = d.share[static_cast<std::size_t>(r)];
      for (std::size_t p = start[static_cast<std::size_t>(r)];
           p < start[static_cast<std::size_t>(r) + 1]; ++p) {
        const std::uint32_t i = by_rank[p];
        ++s.points;
        s.work += point_work(body, i);
        for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k) {
          const std::uint32_t j = body.family.neighbour[k];
          if (own[j] == r || stamp[j] == r) continue;
          stamp[j] = r;
          ++s.ghosts;
        }
      }
    }
  }
  return d;
}

}  // namespace ckpd
