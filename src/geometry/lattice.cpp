#include "src/geometry/lattice.hpp"

#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "bodies/bond_family.hpp"
#include "src/geometry/mesh/mesh_shape.hpp"
#include "src/geometry/work_estimate.hpp"

namespace ckpd {

std::size_t lattice_family_size(int dimension, double spacing, double horizon) {
  // The loop visits (2h + 3)^d offsets: refuse what the loaders should have refused already.
  if (!(horizon > 0 && spacing > 0) ||
      family_size_estimate(dimension, horizon / spacing) > 2 * kMaxFamilySize)
    throw std::invalid_argument("horizon / spacing = " + std::to_string(horizon / spacing) +
                                " gives a family of more than " +
                                std::to_string(2 * kMaxFamilySize) + " lattice offsets");
  const int h = static_cast<int>(std::ceil(horizon / spacing)) + 1;
  const int zr = dimension == 3 ? h : 0;
  std::size_t count = 0;
  for (int z = -zr; z <= zr; ++z)
    for (int y = -h; y <= h; ++y)
      for (int x = -h; x <= h; ++x)
        if ((x || y || z) && within_horizon(Vec3(x, y, z) * spacing, horizon)) ++count;
  return count;
}

LatticeSample sample_lattice(const Shape& shape, int dimension, double dx, double horizon,
                             std::size_t max_points) {
  // A mesh samples itself row by row, with its own estimate (mesh_shape.hpp).
  if (const auto* mesh = dynamic_cast<const MeshShape*>(&shape))
    return mesh->sample(dx, horizon, max_points);
  const Bounds b = shape.bounds();
  if (!b.finite()) throw std::invalid_argument("a body's geometry must be bounded");
  // Counted in saturating arithmetic before any count is cast: an extent of 2e200 at 1 mm
  // must be refused, not wrapped to a handful of sites.
  const std::uint64_t sites = lattice_site_count(b, dimension, dx);
  if (sites > max_points) {
    std::ostringstream msg;
    msg << "sampling would consider " << (sites == kSaturated ? "" : "about ")
        << format_count(sites) << " lattice sites, over the limit of " << max_points
        << " (raise max_points or coarsen the spacing)";
    throw std::invalid_argument(msg.str());
  }
  std::array<long long, 3> n{1, 1, 1};
  for (int d = 0; d < dimension; ++d)
    // Cells across the extent, rounded: extents that are multiples of dx (up to round-off) get
    // exactly that many cell-centred sites. The count above bounds each factor.
    n[d] = std::max(1LL, static_cast<long long>(std::llround((b.hi[d] - b.lo[d]) / dx)));
  const Vec3 centre = (b.lo + b.hi) / 2;
  LatticeSample s;
  const double cell = std::pow(dx, dimension);
  for (long long k = 0; k < n[2]; ++k)
    for (long long j = 0; j < n[1]; ++j)
      for (long long i = 0; i < n[0]; ++i) {
        Vec3 p = centre;
        p.x() += (static_cast<double>(i) - (static_cast<double>(n[0]) - 1) / 2) * dx;
        p.y() += (static_cast<double>(j) - (static_cast<double>(n[1]) - 1) / 2) * dx;
        if (dimension == 3)
          p.z() += (static_cast<double>(k) - (static_cast<double>(n[2]) - 1) / 2) * dx;
        else
          p.z() = 0;
        if (shape.contains(p)) {
          s.position.push_back(p);
          s.volume.push_back(cell);
        }
      }
  s.full_family_volume = static_cast<double>(lattice_family_size(dimension, dx, horizon)) * cell;
  return s;
}

}  // namespace ckpd
