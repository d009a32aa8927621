#include "src/geometry/mesh/mesh_inside.hpp"

#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace ckpd {

namespace {

// The winding numbers of the two half-lines from coordinate x (towards - and +), and whether x
// sits exactly on a crossing; `crossings` sorted.
struct Windings {
  int below = 0, above = 0;
  bool on = false;
};

Windings windings_at(const std::vector<AxisCrossing>& crossings, double x) {
  Windings w;
  int total = 0;
  for (const AxisCrossing& c : crossings) {
    total += c.sign;
    if (c.at < x)
      w.below += c.sign;
    else if (c.at == x)
      w.on = true;
    else
      w.above += c.sign;
  }
  return w;
}

}  // namespace

MeshInside::MeshInside(std::shared_ptr<const TriangleMesh> mesh, InsideTest test)
    : mesh_(std::move(mesh)),
      test_(test),
      rays_{AxisRays(*mesh_, 0), AxisRays(*mesh_, 1), AxisRays(*mesh_, 2)} {}

bool MeshInside::vote(const Vec3& p) const {
  int inside = 0;
  std::vector<AxisCrossing> c;
  for (int a = 0; a < 3; ++a) {
    rays_[a].crossings(p[(a + 1) % 3], p[(a + 2) % 3], c);
    const Windings w = windings_at(c, p[a]);
    if (w.on) return true;
    // Leaving an outward-wound surface towards + crosses a +1, towards - a -1.
    inside += (w.above != 0) + (w.below != 0);
  }
  return inside >= 4;
}

bool MeshInside::contains(const Vec3& p) const {
  if (test_ == InsideTest::tolerant) return vote(p);
  std::vector<AxisCrossing> c;
  rays_[0].crossings(p.y(), p.z(), c);
  const Windings w = windings_at(c, p.x());
  if (w.on) return true;
  if (w.below + w.above != 0) return vote(p);
  return w.above != 0;
}

LatticeSample MeshInside::sample(double dx, double horizon, std::size_t max_points,
                                 double estimated_points) const {
  if (estimated_points > static_cast<double>(max_points)) {
    std::ostringstream msg;
    msg << "sampling would make about " << std::llround(estimated_points)
        << " points (mesh volume / dx^3), over the body's max_points of " << max_points
        << " (raise max_points or coarsen the spacing)";
    throw std::invalid_argument(msg.str());
  }
  Vec3 lo, hi;
  mesh_->bounds(lo, hi);
  std::array<long long, 3> n{1, 1, 1};
  for (int d = 0; d < 3; ++d)
    n[d] = std::max(1LL, static_cast<long long>(std::llround((hi[d] - lo[d]) / dx)));
  const Vec3 centre = (lo + hi) / 2;
  auto site = [&](int d, long long i) {
    return centre[d] + (static_cast<double>(i) - (static_cast<double>(n[d]) - 1) / 2) * dx;
  };
  // Rows along x, one per (y, z) site; each row's inside sites found independently.
  const long long rows = n[1] * n[2];
  std::vector<std::vector<std::uint32_t>> inside(static_cast<std::size_t>(rows));
  std::vector<std::uint8_t> unbalanced(static_cast<std::size_t>(rows), 0);
#pragma omp parallel
  {
    std::vector<AxisCrossing> c;
#pragma omp for schedule(dynamic, 16)
    for (long long r = 0; r < rows; ++r) {
      const long long j = r % n[1], k = r / n[1];
      const double y = site(1, j), z = site(2, k);
      rays_[0].crossings(y, z, c);
      if (c.empty()) continue;
      int total = 0;
      for (const AxisCrossing& x : c) total += x.sign;
      const bool by_vote = test_ == InsideTest::tolerant || total != 0;
      unbalanced[static_cast<std::size_t>(r)] = total != 0;
      // Only sites between the first and last crossing can be inside.
      const long long first =
          std::max(0LL, static_cast<long long>(std::floor((c.front().at - site(0, 0)) / dx)));
      const long long last =
          std::min(n[0] - 1, static_cast<long long>(std::ceil((c.back().at - site(0, 0)) / dx)));
      auto& mine = inside[static_cast<std::size_t>(r)];
      std::size_t next = 0;  // crossings below the site so far
      int below = 0;
      for (long long i = first; i <= last; ++i) {
        const double x = site(0, i);
        bool in;
        if (by_vote) {
          in = vote(Vec3(x, y, z));
        } else {
          while (next < c.size() && c[next].at < x) below += c[next++].sign;
          const bool on = next < c.size() && c[next].at == x;
          in = on || below != 0;  // total is zero, so above = -below
        }
        if (in) mine.push_back(static_cast<std::uint32_t>(i));
      }
    }
  }
  std::size_t count = 0;
  unbalanced_rows_ = 0;
  for (long long r = 0; r < rows; ++r) {
    count += inside[static_cast<std::size_t>(r)].size();
    unbalanced_rows_ += unbalanced[static_cast<std::size_t>(r)];
  }
  if (count > max_points) {
    std::ostringstream msg;
    msg << "sampling found " << count << " points (estimated " << std::llround(estimated_points)
        << "), over the body's max_points of " << max_points;
    throw std::invalid_argument(msg.str());
  }
  LatticeSample s;
  s.position.reserve(count);
  const double cell = dx * dx * dx;
  for (long long r = 0; r < rows; ++r)
    for (std::uint32_t i : inside[static_cast<std::size_t>(r)])
      s.position.emplace_back(site(0, i), site(1, r % n[1]), site(2, r / n[1]));
  s.volume.assign(count, cell);
  s.full_family_volume = static_cast<double>(lattice_family_size(3, dx, horizon)) * cell;
  return s;
}

}  // namespace ckpd
