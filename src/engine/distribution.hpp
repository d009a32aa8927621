#pragma once
// Distributed memory (issue 14, docs/SCALING.md): each rank holds every deformable body only as
// its restriction to the points it owns and their halo (bodies/sub_body.hpp), instead of the whole
// scene. Each step the owners send their ghosts' state forward and the ranks send the partial
// forces their sets put on ghosts back (src/engine/halo_exchange.hpp), so the messages grow with
// the halo, not with the body, and a rank's memory with its share. What the bodies book (strain
// and dissipated energy, failed bonds, damage) is booked by the owners (Body::booked_points) and
// summed over ranks in rank order, the same bits on every rank.
//
// The scenes it takes: deformable bodies with a symmetric-kernel model (the CKPD laws, the PMB
// bond law) and their conditions, rigid bodies and mesh walls (held whole by every rank), in
// contact under the seed law or a DEM law without friction (each rank's contact ghosts:
// contact_ghosts.hpp), without friction or a far field, with a fixed step and a strain measure that
// does not stiffen in compression (distribution_refusal names what is not taken; those scenes run
// on the replicated scheme of force_sharing.hpp).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "src/engine/decomposition.hpp"
#include "src/engine/halo.hpp"
#include "src/engine/halo_exchange.hpp"
#include "src/engine/scene.hpp"
#include "src/engine/simulation.hpp"

namespace ckpd {

// Bytes a step's halo messages carry for `ghosts` ghost points: their displacements and velocities
// from the owners (kStateValues doubles each) and the forces their sets put on them back (3
// doubles; with energy 4).
inline std::uint64_t halo_bytes_per_step(std::uint64_t ghosts, bool with_energy = false) {
  return ghosts * (kStateValues + force_values(with_energy)) * sizeof(double);
}

// Why `scene` cannot run distributed, in words ("body 'ball' is rigid"); empty: it can.
std::string distribution_refusal(const Scene& scene);

struct DistributedScene;

struct DistributedBody {
  // A rigid body is not cut: every rank holds it whole and moves it identically from the same
  // forces (its contact forces are computed on every rank, contact_ghosts.hpp); rank 0 books it.
  bool replicated = false;
  HaloLinks links;  // links.points: each local point's index in the whole body; links.owned
  HaloBuffers buffers;
  std::size_t whole_points = 0;
  std::vector<int> owner;  // rank 0 only (for gather): the owner of each point of the whole body
};

class Distribution {
 public:
  int rank() const { return rank_; }
  int ranks() const { return ranks_; }
  const DistributedBody& body(std::size_t b) const { return bodies_[b]; }
  std::size_t body_count() const { return bodies_.size(); }
  const Decomposition& decomposition() const { return decomposition_; }
  // Facts of the whole scene, fixed before it was restricted: the step, the wave speed scale of
  // the instability guard (m/s, before the factor 10), the pre-existing failed bonds per body.
  const StepChoice& step_choice() const { return step_choice_; }
  double wave_speed() const { return wave_speed_; }
  // Per body, the contact stiffness bound of the whole scene (contact_coupling.hpp).
  const std::vector<double>& contact_stiffness() const { return contact_stiffness_; }
  const std::vector<std::size_t>& initially_failed() const { return initially_failed_; }

  // Forward: the ghosts' displacements and velocities from their owners. A collective.
  void exchange_state(Scene& local);
  // Backward: every owned point's force density (and with energy its strain energy density)
  // becomes the sum over ranks, in rank order, of the ranks' partials. A collective.
  void sum_forces(Scene& local, bool with_energy);
  // values[0, summed) <- their sums over ranks in rank order (the same bits on every rank), the
  // rest <- their largest over ranks (one message for both). A collective.
  void sum_and_max(std::vector<double>& values, std::size_t summed);

  // A point chosen over ranks: the one with the largest `rank_key` (ties: the lower body, then
  // global point index), as every rank sees it.
  struct Choice {
    double key = -1;                  // -1: none on this rank
    std::size_t body = 0, point = 0;  // point: index in the whole body
    Vec3 reference = Vec3::Zero();
  };
  // Each rank proposes its candidate (point as a local index of body `body`); returns the chosen
  // one with its whole-body index and reference position. A collective.
  Choice choose(const Scene& local, double key, std::size_t body, std::size_t local_point);

  // Rank 0's `whole` bodies (their points and bonds as built, every rank's state and bond flags
  // gathered from the owners: displacement, velocity, acceleration, force and strain energy
  // densities, bond_intact). A collective; the other ranks' `whole` is not touched.
  void gather(const Scene& local, Scene& whole);
  // The reverse, for a restart: every point of this rank's part (owned and ghost) takes its state
  // and bond flags from `whole` (the scene a checkpoint was read into). Not a collective.
  void scatter(const Scene& whole, Scene& local) const;

 private:
  friend struct DistributedScene;
  friend DistributedScene distribute_scene(Scene& whole, int rank, int ranks);
  int rank_ = 0, ranks_ = 1;
  std::vector<DistributedBody> bodies_;
  Decomposition decomposition_;
  StepChoice step_choice_;
  double wave_speed_ = 0;
  std::vector<double> contact_stiffness_;
  std::vector<std::size_t> initially_failed_;
  std::vector<double> scratch_, proposal_;
  std::vector<unsigned char> bytes_, gathered_bytes_;
};

struct DistributedScene {
  Scene local;  // this rank's restrictions, with the conditions that act on their points
  std::unique_ptr<Distribution> distribution;
};

// Rank `rank`'s part of `whole` over `ranks` ranks (decomposition.hpp's bisection): each body
// restricted to its owned points and their halo (owned_centres and booked_points set to the owned
// points), the conditions moved from `whole` into the parts with their points mapped to local
// indices. `whole` keeps its bodies (rank 0 gathers into them for output; other ranks may free
// them). Throws std::invalid_argument with distribution_refusal's reason for a scene it does not
// take, or decompose's for fewer points than ranks.
DistributedScene distribute_scene(Scene& whole, int rank, int ranks);

}  // namespace ckpd
