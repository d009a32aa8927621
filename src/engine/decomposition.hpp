#pragma once
// The spatial decomposition of a scene's deformable points over ranks (issue 14, first step: the
// partition and its halo; no message passing yet). Recursive coordinate bisection over the
// points of all deformable bodies together, in the reference configuration: each cut is
// perpendicular to the longest side of the current group's box and falls where the work on its
// two sides is in the ratio of the ranks they get. The work of a point is its share of the
// interactions it takes part in, weighted by their cost (point_work), so a rank holding surface
// points (smaller families) gets more of them.
//
// The halo of a rank is every point, not its own, in the family of one of its points: the
// kernels' sets centred at an owned point reach no farther (all vertices of a set lie in each
// vertex's family), and the energy-consistent weights and the damage rules read only the bonds
// among a set's vertices, so one horizon is enough for forces and for bond failure decided
// identically on every rank that holds a bond. Rigid bodies and mesh walls have no bonds and are
// not decomposed (their motion is a reduction over ranks).
#include <cstdint>
#include <vector>

#include "bodies/body.hpp"

namespace ckpd {

// Estimated cost of point i's interactions, in floating-point operations per step: its share of
// each bond (1/2), triangle (1/3) and tetrahedron (1/4) it is a vertex of, at the operation counts
// of the symmetric kernel (docs/PERFORMANCE.md: about 23 per bond, 70 per triangle, 26 per
// tetrahedron on the general path). body.n2 and body.n3 count ordered sets (2 and 6 orders).
double point_work(const Body& body, std::size_t i);

struct RankShare {
  std::uint64_t points = 0;  // owned
  std::uint64_t ghosts = 0;  // halo points (each counted once per rank; distribution.hpp's
                             // halo_bytes_per_step gives what they cost a step)
  double work = 0;           // sum of point_work over the owned points
};

struct Decomposition {
  int ranks = 1;
  // owner[b][i]: the rank owning point i of bodies[b] (every point of a rigid body: -1).
  std::vector<std::vector<int>> owner;
  std::vector<RankShare> share;  // per rank
  // The largest rank's work over the mean: 1 is a perfect balance.
  double imbalance() const;
  // Halo points over all ranks.
  std::uint64_t ghosts() const {
    std::uint64_t total = 0;
    for (const RankShare& s : share) total += s.ghosts;
    return total;
  }
};

// Decomposes the deformable bodies among `bodies` (those with bonds or a force model; `rigid[b]`
// true marks the ones to leave out) over `ranks` ranks. Deterministic: ties in a coordinate are
// broken by body, then point index. Throws std::invalid_argument when `ranks` < 1 or when there
// are fewer deformable points than ranks.
Decomposition decompose(const std::vector<const Body*>& bodies, const std::vector<bool>& rigid,
                        int ranks);

}  // namespace ckpd
