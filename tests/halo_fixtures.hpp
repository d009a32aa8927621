#pragma once
// Shared by the halo-exchange tests (in one process and under mpirun): a block pulled apart
// from its middle until it fractures, velocity Verlet for whole bodies and for a rank's owned
// points, and the replicated scheme's forces (every rank's centres on the whole body, summed in
// rank order) that the halo exchange must reproduce.
#include <random>
#include <vector>

#include "bodies/symmetric_kernel.hpp"
#include "kernel_comparison.hpp"

namespace halo_fixtures {

using kernel_comparison::Body;
using kernel_comparison::BodyDefinition;
using kernel_comparison::Vec3;

constexpr int kSteps = 200;  // the MPI case tests' length (tests/mpi/)

// Velocity proportional to x - centre (100 m/s across), small random displacements, a critical
// stretch the pull exceeds within kSteps steps at half the stable step.
inline Body pulled_block(int dimension, std::mt19937& rng) {
  using namespace kernel_comparison;
  // m = 2.015 in 3D keeps the tests fast (a tenth of the tetrahedra of m = 3).
  const double m = dimension == 3 ? 2.015 : kM;
  const Scene s{"block",
                dimension,
                dimension == 3 ? 0.3 : 0.4,
                0.0,
                dimension == 3 ? 10 : 20,
                dimension == 3 ? 5 : 10,
                dimension == 3 ? 5 : 1,
                false,
                m};
  BodyDefinition d = block(s.dimension, s.nx, s.ny, s.nz, constants_for(s), 0.0, rng, m);
  d.critical_stretch = 4e-3;
  Body body = ckpd::make_body(d);
  perturb(body, 1e-4, rng);
  double lo = 1e300, hi = -1e300;
  for (const Vec3& p : body.reference_position) {
    lo = std::min(lo, p.x());
    hi = std::max(hi, p.x());
  }
  for (std::size_t i = 0; i < body.size(); ++i) {
    const double t = (body.reference_position[i].x() - 0.5 * (lo + hi)) / (hi - lo);
    body.velocity[i] = Vec3(100.0 * t, 0, 0);  // m/s
  }
  return body;
}

// Kick and drift of the points with move[i] != 0 (all: null).
inline void kick(Body& body, double h, const std::vector<std::uint8_t>* move = nullptr) {
  for (std::size_t i = 0; i < body.size(); ++i)
    if (move == nullptr || (*move)[i]) body.velocity[i] += h * body.force_density[i] / body.density;
}
inline void drift(Body& body, double dt, const std::vector<std::uint8_t>* move = nullptr) {
  for (std::size_t i = 0; i < body.size(); ++i)
    if (move == nullptr || (*move)[i]) body.displacement[i] += dt * body.velocity[i];
}

// The replicated scheme's forces: each rank's centres on the whole body, summed in rank order.
inline void replicated_forces(Body& body, const std::vector<int>& owner, int ranks) {
  std::vector<Vec3> sum(body.size(), Vec3::Zero());
  for (int r = 0; r < ranks; ++r) {
    body.owned_centres.assign(body.size(), 0);
    for (std::size_t i = 0; i < body.size(); ++i) body.owned_centres[i] = owner[i] == r;
    ckpd::compute_internal_force_symmetric(body, false);
    for (std::size_t i = 0; i < body.size(); ++i) sum[i] += body.force_density[i];
  }
  body.force_density = sum;
  body.owned_centres.clear();
}

// How a rank's restriction compares with the whole runs after the steps.
struct Agreement {
  std::size_t not_bitwise = 0;      // owned points whose u or v differ from the replicated run's
  std::size_t failures_differ = 0;  // bonds the rank holds whose flag differs from the whole run
  double displacement = 0;          // largest |u - u_whole| over owned points
};

inline Agreement compare(const Body& part, const std::vector<std::uint32_t>& global,
                         const std::vector<std::uint8_t>& owned, const Body& whole,
                         const Body& replicated) {
  Agreement a;
  for (std::size_t l = 0; l < part.size(); ++l) {
    const std::size_t g = global[l];
    if (owned[l]) {
      a.not_bitwise += part.displacement[l] != replicated.displacement[g] ||
                       part.velocity[l] != replicated.velocity[g];
      a.displacement =
          std::max(a.displacement, (part.displacement[l] - whole.displacement[g]).norm());
    }
    std::size_t e = whole.family.offset[g];
    for (std::size_t m = part.family.offset[l]; m < part.family.offset[l + 1]; ++m) {
      while (whole.family.neighbour[e] != global[part.family.neighbour[m]]) ++e;
      a.failures_differ += part.bond_intact[m] != whole.bond_intact[e];
    }
  }
  return a;
}

}  // namespace halo_fixtures
