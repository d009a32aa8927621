#pragma once
// Contact between points and mesh walls (mesh_wall.hpp): each point within l_c of a wall feels
// the point law integrated over a rigid half-space bounded by the wall's tangent plane at the
// nearest surface point (wall_law.hpp), along the outward normal there. The reaction (the
// opposite force, on the same line of action) goes to the wall's carrier points, spread so that
// their total force and torque about the wall's centre are the reaction's: momentum and angular
// momentum are conserved, and the rigid motion of a free wall responds to it exactly.
#include <cstddef>
#include <vector>

#include "contact/contact_settings.hpp"

namespace ckpd {

class MeshWallContact {
 public:
  struct Pair {
    std::size_t body = 0, wall = 0;  // indices into the bodies
    double radius = 0;               // l_c
    double coefficient = 0;          // c = 9 Ccon / (pi delta^5) of the point's side
  };
  // `bodies` as the contact manager holds them; walls have ContactBody::wall set.
  MeshWallContact(const std::vector<ContactBody>& bodies, std::vector<Pair> pairs);

  // Adds the contact force densities to the points and the reactions to the carriers.
  void add_forces();
  double energy() const { return energy_; }
  std::size_t points_in_contact() const { return touching_; }
  bool pair_touching(std::size_t k) const { return pair_touching_[k] != 0; }
  std::size_t pairs() const { return pairs_.size(); }

 private:
  const std::vector<ContactBody>& bodies_;
  std::vector<Pair> pairs_;
  std::vector<Vec3> force_;  // scratch: per point of the pair's body, its force density
  std::vector<double> point_energy_;
  std::vector<std::uint8_t> pair_touching_;
  double energy_ = 0;
  std::size_t touching_ = 0;
};

}  // namespace ckpd
