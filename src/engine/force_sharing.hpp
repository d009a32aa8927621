#pragma once
// Distributed force work over replicated state (issue 14). Every rank holds and integrates the
// whole scene; the symmetric kernel of each deformable body evaluates only the sets centred at
// the points this rank owns in the decomposition (decomposition.hpp, Body::owned_centres), and
// the ranks' partial force (and energy) buffers are then added in rank order, the same sum on
// every rank. Everything else (bond failure, damage booking, contact, rigid bodies, conditions,
// the stable step and the guards) runs redundantly on every rank from identical inputs, so every
// rank takes the same decisions.
#include <cstdint>
#include <vector>

#include "src/engine/decomposition.hpp"
#include "src/engine/scene.hpp"

namespace ckpd {

// The decomposition of the scene's deformable bodies over `ranks`, and for rank `rank` each
// such body's Body::owned_centres. A body not evaluated by the symmetric kernel's centre loop
// (the state-based model) keeps it empty: every rank evaluates it whole and it is not summed.
// With one rank nothing is set (the run is exactly a single-process run). Throws
// std::invalid_argument when there are fewer deformable points than ranks.
Decomposition share_force_work(Scene& scene, int rank, int ranks);

// Whether body b's force work is shared over ranks (owned_centres set).
inline bool shares_force_work(const Body& b) {
  return !b.owned_centres.empty();
}

// Whether share_force_work shares a body's work at several ranks: not a rigid body's, the
// state-based solid's (two-pass kernel) or a body's with a far field (its linear rows overwrite
// whole points' forces, which a sum over ranks would count once per rank).
bool force_work_can_be_shared(const SceneBody& sb);

// The doubles a rank sends per combination for one sharing body: 3 per point, plus one per point
// and one per body in an evaluation with energy.
inline std::size_t shared_force_values(const Body& b, bool with_energy) {
  return (with_energy ? 4 : 3) * b.size() + (with_energy ? 1 : 0);
}

// The doubles a rank sends per combination: shared_force_values of every sharing body.
std::size_t shared_force_values(const Scene& scene, bool with_energy);

struct ForceSharingBuffers {
  std::vector<double> values, gathered;
};

// After every sharing body's kernel has run on this rank's centres: their force_density (and,
// with energy, strain_energy_density and the inverted-set counts inverted[b]) become the sums
// over ranks, in rank order. A collective: every rank calls it at the same point.
void sum_shared_forces(Scene& scene, bool with_energy, std::vector<std::uint64_t>& inverted,
                       ForceSharingBuffers& buffers);

}  // namespace ckpd
