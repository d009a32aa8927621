#pragma once
// Contact between points and mesh walls (mesh_wall.hpp): each point within l_c of a wall feels
// the point law integrated over a rigid half-space bounded by the wall's tangent plane at the
// nearest surface point (wall_law.hpp), along the outward normal there. The reaction (the
// opposite force, on the same line of action) goes to the wall's carrier points, spread so that
// their total force and torque about the wall's centre are the reaction's: momentum and angular
// momentum are conserved, and the rigid motion of a free wall responds to it exactly.
//
// Under a DEM law (dem_law.hpp) the point is a sphere of radius l_c against the wall's surface:
// overlap l_c - h along the outward normal, the contact at the nearest surface point p, whose
// velocity is the wall's rigid motion there. The reaction then acts at p (torque about the
// wall's centre from p), and a spinning point body gets the couple (p - x^i) x F. Each point
// keeps one tangential spring per wall, stamped with the evaluation that wrote it.
#include <cstddef>
#include <memory>
#include <vector>

#include "contact/contact_history.hpp"
#include "contact/contact_settings.hpp"
#include "contact/mesh_wall.hpp"

namespace ckpd {

class MeshWallContact {
 public:
  struct Pair {
    std::size_t body = 0, wall = 0;     // indices into the bodies
    double radius = 0;                  // l_c
    double coefficient = 0;             // c = 9 Ccon / (pi delta^5) of the point's side
    std::shared_ptr<const DemLaw> dem;  // null: the seed law integrated over the wall
  };
  // `bodies` as the contact manager holds them; walls have ContactBody::wall set.
  MeshWallContact(const std::vector<ContactBody>& bodies, std::vector<Pair> pairs);

  // Adds the contact force densities to the points and the reactions to the carriers. `dt` and
  // `evaluation` as ContactManager::add_forces has them (DEM springs and dissipation).
  void add_forces(double dt = 0, std::uint64_t evaluation = 0);
  double energy() const { return energy_; }
  // Dissipated in the last add_forces by dashpots and by sliding.
  double damping_dissipated() const { return damping_; }
  double friction_dissipated() const { return friction_; }
  std::vector<ContactHistoryRow> history(std::uint64_t evaluation) const;
  void restore_history(std::uint64_t evaluation, const std::vector<ContactHistoryRow>& rows);
  std::size_t points_in_contact() const { return touching_; }
  bool pair_touching(std::size_t k) const { return pair_touching_[k] != 0; }
  std::size_t pairs() const { return pairs_.size(); }

 private:
  void add_dem_forces(std::size_t k, double dt, std::uint64_t evaluation);
  // Adds pair k's point forces (force_, scratch of the pass) to the points, their reaction to
  // the wall's carriers, and the energy and dissipation to the totals.
  void book(std::size_t k, const MeshWall::Pose& pose, double dt);
  const std::vector<ContactBody>& bodies_;
  std::vector<Pair> pairs_;
  std::vector<Vec3> force_;  // scratch: per point of the pair's body, its force density
  std::vector<double> point_energy_;
  // DEM scratch, per point: contact point, couple, dissipation; springs per pair and point.
  std::vector<Vec3> at_, couple_;
  std::vector<double> point_damping_, point_slip_;
  std::vector<std::vector<Vec3>> spring_;
  std::vector<std::vector<std::uint64_t>> stamp_;
  double damping_ = 0, friction_ = 0;
  std::vector<std::uint8_t> pair_touching_;
  double energy_ = 0;
  std::size_t touching_ = 0;
};

}  // namespace ckpd
