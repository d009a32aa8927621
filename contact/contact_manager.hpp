#pragma once
// Contact between any number of bodies (THEORY.md section 5), in two phases.
//
// Broad phase: each body's box of current points, inflated by half of (l_c + skin) of its
// widest contact law, goes into an FCL tree that yields the pairs of overlapping boxes. For each
// such pair only the points that can come within l_c of the other body before the next rebuild
// are kept (those inside the other body's box grown by l_c and both bodies' drift allowances).
// The candidates stay valid while no point has moved more than half its body's skin since the
// build (as LAMMPS neighbour lists do), so the tree is rebuilt only then.
//
// Narrow phase, every step: the kept points of each side are binned in a cell list and every
// kept point sums the force of the other side's points within l_c. Each point's sum is its own
// (no two threads write one point) and runs in a fixed order, so the result does not depend on
// the thread count; the two sides of a point pair compute the same r and the same scalar, so
// their forces are exactly opposite when the pair uses one coefficient.
//
// Mesh walls (ContactBody::wall) take no part in either phase: their partners' points meet
// their surfaces in MeshWallContact, whose forces and energy are added here.
//
// Self-contact: a body's own points that are not joined by an intact bond repel with the same
// law (fragments of a broken body must not pass through each other).
#include <cstdint>
#include <memory>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

#include "contact/broad_phase.hpp"
#include "contact/contact_history.hpp"
#include "contact/contact_settings.hpp"
#include "contact/mesh_wall_contact.hpp"
#include "contact/point_grid.hpp"

namespace ckpd {

struct ContactStatistics {
  std::uint64_t rebuilds = 0;          // broad-phase builds (the first one included)
  std::uint64_t pairs_checked = 0;     // body pairs whose narrow phase ran, summed over evaluations
  std::uint64_t points_binned = 0;     // narrow-phase work: points put into cell lists
  std::uint64_t point_pair_tests = 0;  // narrow-phase work: point distances evaluated
  std::size_t candidate_pairs = 0;     // body pairs (self-contact included) now
  std::size_t candidate_pairs_peak = 0;
  std::size_t points_in_contact = 0;  // point pairs closer than l_c now
  // Their ends this process books (a pair's two ends, a point on a wall counted twice): summed over
  // distributed ranks, twice the scene's pairs.
  std::uint64_t contact_ends = 0;
  std::size_t points_in_contact_peak = 0;
  std::size_t touching_pairs = 0;  // body pairs with a point pair closer than l_c now
  std::size_t touching_pairs_peak = 0;
  double seconds = 0;  // wall time spent in add_forces
};

class ContactManager {
 public:
  // The arrays behind the views must stay valid until the next rebind. Throws
  // std::invalid_argument like ContactSettings::law.
  ContactManager(std::vector<ContactBody> bodies, ContactSettings settings);
  ~ContactManager();

  // New views of the same bodies (same order and sizes): the owner calls it whenever the arrays
  // behind the views may have moved (the engine does before every evaluation).
  void rebind(const std::vector<PointSet>& points);

  // Adds every point's contact force density to its view's force_density (at the current
  // positions) and sets energy(). `dt`: the time since the last evaluation (0 for the first),
  // over which DEM laws advance their tangential springs and book their dissipation; the
  // velocities in the views are those of that interval (the integrator's midpoint velocities).
  void add_forces(double dt = 0);
  // Contact energy at the last add_forces: sum over point pairs of c V^i V^j (l_c - r)^2 / 2
  // (see contact_law.hpp for c when the two sides differ); for DEM laws their elastic energy
  // and that of the tangential springs.
  double energy() const { return energy_; }
  // Energy dissipated so far by the DEM laws' dashpots and by friction (sliding).
  double damping_dissipated() const { return damping_dissipated_; }
  double friction_dissipated() const { return friction_dissipated_; }
  // Whether any pair has a tangential history (a DEM law with friction).
  bool has_history() const { return friction_; }
  // What a checkpoint keeps: with every view's state, restoring it continues bit for bit.
  struct HistoryState {
    std::uint64_t evaluation = 0;
    double damping_dissipated = 0, friction_dissipated = 0;
    std::vector<ContactHistoryRow> rows;
  };
  HistoryState history() const;
  void restore_history(const HistoryState& state);
  const ContactStatistics& statistics() const { return stats_; }
  // Adds an earlier manager's counts and peaks to this one's (a manager that takes over from
  // another with new views: src/engine/contact_ghosts.hpp).
  void carry_statistics(const ContactStatistics& earlier);
  // Whether any pair of distinct bodies can interact (else no broad phase exists).
  bool has_broad_phase() const { return broad_ != nullptr; }

 private:
  struct Pair;
  struct Target;  // one point that has partners, and which pairs they are in
  bool drifted_beyond_skin() const;
  void rebuild();
  void index_targets();

  std::vector<ContactBody> bodies_;
  ContactSettings settings_;
  std::vector<std::size_t> members_;  // bodies in the broad phase
  std::size_t member_points_ = 0;     // their points, all together
  std::vector<double> margin_;        // per body: box inflation, half of the widest l_c + skin
  std::vector<double> drift_limit_;   // per body: how far a point may move between builds
  std::unique_ptr<BroadPhase> broad_;
  std::unique_ptr<MeshWallContact> walls_;             // pairs with a mesh wall; null without any
  std::vector<std::vector<Vec3>> built_displacement_;  // per member body, at the last build
  std::vector<Pair> self_pairs_;
  // The pairs of bodies found by the last rebuild: the first pair_count_ of pairs_ (the rest are
  // kept with their buffers for the next rebuild: no allocation in a time step).
  std::vector<Pair> pairs_;
  std::size_t pair_count_ = 0;
  std::vector<std::optional<PairLaw>> pair_law_;  // per body pair a * n + b (a <= b), at setup
  // rebuild's and index_targets' buffers, kept between calls.
  std::vector<Box3> tight_, inflated_;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> broad_pairs_;
  std::vector<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>> target_entries_;
  std::vector<Target> targets_;
  std::vector<std::uint32_t> target_refs_;  // per target: pair * 2 + side, into all_pairs_
  std::vector<Pair*> all_pairs_;
  std::vector<double> target_energy_;
  std::vector<std::uint32_t> target_contacts_, target_tests_;
  std::vector<std::uint8_t> pair_touching_;  // per pair of all_pairs_, this evaluation
  bool built_ = false;
  double energy_ = 0;
  // DEM laws: per target its dissipation and couple this evaluation; the springs.
  struct DemTotals {
    double damping = 0, friction = 0;
    Vec3 couple = Vec3::Zero();
  };
  bool dem_ = false, friction_ = false;
  std::vector<DemTotals> target_dem_;
  PairHistory history_;
  std::uint64_t evaluation_ = 0;
  double damping_dissipated_ = 0, friction_dissipated_ = 0;
  ContactStatistics stats_;
};

}  // namespace ckpd
