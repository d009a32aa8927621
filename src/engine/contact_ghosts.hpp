#pragma once
// Contact on distributed memory (issue 14, docs/SCALING.md "Contact across ranks"). A rank holds
// each body as its restriction to the points it owns and their halo (distribution.hpp); contact
// needs, besides, every point of any body that can come within l_c of a point it owns. Those are
// its contact ghosts, chosen by the ranks themselves from the current positions:
//
// - Selection (a collective): each rank's box of its owned points (all bodies together) goes to
//   every rank; each owner sends every other rank the owned points inside that rank's box grown
//   by the reach R = l_c + s (the widest law's radius and skin), with their reference position
//   and volume. A point not sent was farther than R from every point of the receiver at the
//   selection; while no point has moved more than s / 2 since (one collective test a step), no
//   such pair comes within R - s = l_c, so the selection stays complete, as a Verlet list does.
// - Every step the owners send their contact ghosts' displacements and velocities (6 doubles a
//   ghost); a rank's view of a body is its owned points and its contact ghosts of that body in
//   increasing whole-body index, and the contact manager computes only the owned points' forces
//   (PointSet::computed): the ghosts are partners, and no force goes back.
//
// Each owned point sums its partners in (body, point) order (contact_manager.hpp), and a view
// keeps the whole body's order, so its force is the single process's bit for bit whatever the
// rank count. Each point books half of each of its pairs' energy: the energies of the ranks' owned
// points add up to the scene's. Self-contact asks the owned point's family, which the
// restriction holds whole.
//
// Rigid bodies are held whole by every rank (distribution.hpp): each rank computes every rigid
// point's contact force, from all its partners (each owner sends the points within the reach of a
// rigid body's box to every rank), so every rank moves the rigid body alike, with the single
// process's forces; rank 0 alone books their energy share (PointSet::booked).
//
// Mesh walls are rigid bodies too, but a wall meets each point alone: a rank computes its owned
// points' wall forces and spreads the reactions of the points it books to the wall's carriers,
// and the carriers' forces are summed over ranks in rank order (so a free wall moves alike on
// every rank, within round-off of the single process, whose sum runs in point order).
//
// DEM laws without friction: each end of a pair computes the same contact from the same state
// (contact_manager.hpp), so an owned point's force is again the single process's; the dashpots'
// dissipation is booked by the points' owners (rank 0 for rigid bodies) and summed over ranks by
// the Simulation.
//
// Taken: deformable and rigid bodies and mesh walls under the seed law (contact_law.hpp) and DEM
// laws without friction; friction is refused by distribution_refusal (its tangential springs are
// written by one end of a pair and read by the other, and its couples go to the point's cluster,
// which may be another rank's), and such scenes run on the replicated scheme.
#include <cstdint>
#include <memory>
#include <vector>

#include "contact/contact_manager.hpp"
#include "src/engine/scene.hpp"

namespace ckpd {

class Distribution;

class ContactGhosts {
 public:
  // `local`: this rank's scene (its restrictions), cut by `distribution`; both must outlive this.
  ContactGhosts(Scene& local, const Distribution& distribution);
  ~ContactGhosts();

  // Adds each owned point's contact force density to its body's force_density, at the current
  // positions; `dt` as ContactManager::add_forces. Selects the ghosts anew first when a point has
  // moved more than half the skin since the last selection. A collective.
  void add_forces(double dt);
  // The manager of the current views: its energy() is this rank's owned points' share.
  const ContactManager& manager() const { return *manager_; }
  void restore_history(const ContactManager::HistoryState& state);
  // The next add_forces selects anew (a restart's state is not the one the ghosts were chosen at).
  void invalidate() { valid_ = false; }

  std::uint64_t selections() const { return selections_; }
  std::size_t ghosts() const;  // contact ghosts this rank holds now, all bodies
  double reach() const { return reach_; }

 private:
  struct View;
  void select();
  // The views from the owned points and the selection just received (receive_buffer_), and a new
  // manager on them.
  void build_views();
  void refresh();
  bool drifted() const;
  void sum_wall_reactions();

  Scene& local_;
  const Distribution& distribution_;
  double reach_ = 0, drift_limit_ = 0;
  std::vector<View> views_;
  std::vector<PointSet> points_;  // the manager's views of them
  std::unique_ptr<ContactManager> manager_;
  // Per other rank: the owned points sent there, as (body, local index), and where the points
  // received from there go, as (body, view index); both in the order of the messages.
  std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> send_, receive_;
  std::vector<std::vector<double>> send_buffer_, receive_buffer_;
  std::vector<double> gathered_, wall_forces_;
  bool valid_ = false;
  std::uint64_t selections_ = 0;
};

}  // namespace ckpd
