#include "contact/contact_stiffness.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <tuple>
#include <utility>

#include "contact/dem_law.hpp"

namespace ckpd {

std::size_t max_lattice_sites_in_ball(double radius, double spacing, int dimension) {
  const double ratio = radius / spacing;
  if (ratio > 4) return static_cast<std::size_t>(std::pow(2 * ratio + 1, dimension));
  constexpr int kSamples = 32;
  // Every centre in the cell is within this distance of a sample, so the sites within `reach`
  // of the nearest sample include all sites within `radius` of the centre.
  const double cover = 0.5 * std::sqrt(static_cast<double>(dimension)) / kSamples;
  const double reach = (ratio + cover) * (1 + 1e-12);
  const int range = static_cast<int>(std::ceil(reach)) + 1;
  const int zs = dimension == 3 ? kSamples : 1;
  const int zr = dimension == 3 ? range : 0;
  std::size_t best = 0;
  for (int a = 0; a < kSamples; ++a)
    for (int b = 0; b < kSamples; ++b)
      for (int c = 0; c < zs; ++c) {
        const double cx = (a + 0.5) / kSamples, cy = (b + 0.5) / kSamples,
                     cz = dimension == 3 ? (c + 0.5) / kSamples : 0.0;
        std::size_t count = 0;
        for (int i = -range; i <= range; ++i)
          for (int j = -range; j <= range; ++j)
            for (int k = -zr; k <= zr; ++k) {
              const double dx = i - cx, dy = j - cy, dz = k - cz;
              if (dx * dx + dy * dy + dz * dz <= reach * reach) ++count;
            }
        best = std::max(best, count);
      }
  return best;
}

namespace {

// A DEM law's share for the points of `x` against partners of `y` (y a wall when `wall`): the
// row sum 2 N K / V^x with K the law's normal stiffness at the deepest stable overlap l_c / 2
// (as for the seed law), raised by the tangential spring where it is stiffer and by the dashpot
// (velocity Verlet with damping ratio zeta is stable up to omega dt = 2 (sqrt(1 + zeta^2) - zeta)),
// over the smallest and the largest point of x against the largest of y. A free DEM sphere's
// tangential mode also turns it: at its surface it meets the spring with the reduced mass
// (1/m + R^2/I)^-1 = m / 3.5 for the solid sphere, so its tangential stiffness counts 3.5 times.
double dem_bound(const DemLaw& law, double radius, const ContactBody& xb, const PointSet* y,
                 double partners) {
  const PointSet& x = xb.points;
  const double spin = xb.sphere_radius > 0 && !xb.prescribed ? 3.5 : 1.0;
  // A set without points (a rank's empty part of a body) feels nothing.
  if (x.volume.empty() || (y && y->volume.empty())) return 0;
  auto extremes = [](const PointSet& s) {
    const auto [lo, hi] = std::minmax_element(s.volume.begin(), s.volume.end());
    return std::pair<double, double>(*lo, *hi);
  };
  const auto [x_small, x_large] = extremes(x);
  const double y_large = y ? extremes(*y).second : 0;
  const double zeta = law.damping_ratio();
  const double damping = 1 / std::pow(std::sqrt(1 + zeta * zeta) - zeta, 2);
  double k = 0;
  for (double vx : {x_small, x_large}) {
    const LawPoint here{vx, x.density * vx};
    const LawPoint there = y ? LawPoint{y_large, y->density * y_large}
                             : LawPoint{0, std::numeric_limits<double>::infinity()};
    const NormalResponse r = law.normal(0.5 * radius, here, there, y == nullptr);
    const double stiffest =
        std::max(r.stiffness, law.friction > 0 ? spin * r.tangential_stiffness : 0);
    k = std::max(k, 2 * partners * stiffest * damping / vx);
  }
  return kContactResolution * k;
}

}  // namespace

std::vector<double> contact_stiffness_bounds(const ContactSettings& settings,
                                             const std::vector<ContactBody>& bodies) {
  std::vector<double> k(bodies.size(), 0.0);
  if (!settings.present) return k;
  std::vector<double> largest_volume(bodies.size(), 0.0);
  for (std::size_t b = 0; b < bodies.size(); ++b)
    for (double v : bodies[b].points.volume) largest_volume[b] = std::max(largest_volume[b], v);
  // Many bodies share a spacing and a radius: count lattice sites once per combination.
  std::map<std::tuple<double, double, int>, std::size_t> sites;
  auto sites_in_ball = [&](double radius, double spacing, int dimension) {
    auto [it, fresh] = sites.try_emplace({radius, spacing, dimension}, 0);
    if (fresh) it->second = max_lattice_sites_in_ball(radius, spacing, dimension);
    return static_cast<double>(it->second);
  };
  for (std::size_t a = 0; a < bodies.size(); ++a)
    for (std::size_t b = a; b < bodies.size(); ++b) {
      const std::optional<PairLaw> law = settings.law(bodies, a, b);
      if (!law) continue;
      const int dim = bodies[a].points.dimension;
      if (law->dem) {
        // Lattice sites of the partner within l_c; a point set without a lattice (spacing 0) is
        // taken as one partner at a time.
        auto partners = [&](const ContactBody& y) {
          return y.points.spacing > 0 ? sites_in_ball(law->radius, y.points.spacing, dim) : 1.0;
        };
        if (bodies[a].wall || bodies[b].wall) {
          const std::size_t point_side = bodies[a].wall ? b : a;
          if (!bodies[point_side].wall)
            k[point_side] = std::max(
                k[point_side], dem_bound(*law->dem, law->radius, bodies[point_side], nullptr, 1.0));
          continue;
        }
        k[a] = std::max(k[a], dem_bound(*law->dem, law->radius, bodies[a], &bodies[b].points,
                                        partners(bodies[b])));
        k[b] = std::max(k[b], dem_bound(*law->dem, law->radius, bodies[b], &bodies[a].points,
                                        partners(bodies[a])));
        continue;
      }
      if (bodies[a].wall || bodies[b].wall) {
        // A point against a mesh wall: the wall is a dense half-space (wall_law.hpp), so the
        // partner sum N V^j becomes the volume of the ball of radius l_c (4 pi/3 l_c^3), a bound
        // on the law's largest normal stiffness 4 pi/27 l_c^3 with room for edges and corners.
        // The wall's own carriers feel nothing of it.
        const std::size_t point_side = bodies[a].wall ? b : a;
        const double c = law->coefficient[point_side == a ? 0 : 1];
        const double ball = 4.0 / 3 * std::numbers::pi * std::pow(law->radius, 3);
        if (!bodies[point_side].wall)
          k[point_side] = std::max(k[point_side], kContactResolution * 2 * c * ball);
        continue;
      }
      // Point of a feels the partners of b, and the other way round.
      k[a] = std::max(k[a], kContactResolution * 2 * law->coefficient[0] *
                                sites_in_ball(law->radius, bodies[b].points.spacing, dim) *
                                largest_volume[b]);
      k[b] = std::max(k[b], kContactResolution * 2 * law->coefficient[1] *
                                sites_in_ball(law->radius, bodies[a].points.spacing, dim) *
                                largest_volume[a]);
    }
  return k;
}

}  // namespace ckpd
