#pragma once
// What contact sees of a body: a set of points with their state, not the body. The engine builds
// one view per body (src/engine/contact_coupling.hpp) before every contact evaluation, since the
// arrays behind the spans may be reallocated between steps (a checkpoint restore replaces them);
// on distributed memory a rank hands contact its owned points and their contact ghosts through
// the same view (`computed` marks the owned ones).
//
// Positions are kept as reference + displacement (x = X + u, the sum every part of the code
// forms the same way, so results stay bit for bit those of the body's own current_position); the
// displacement also serves the broad phase's drift test. Whether two points are joined by an
// intact bond (self-contact must skip them) is a query answered by the owner of the bonds.
#include <cstdint>
#include <span>
#include <string_view>

#include "bodies/vec.hpp"

namespace ckpd {

// bonded(context, i, j): true when points i and j are joined by a bond that has not failed.
struct BondQuery {
  const void* context = nullptr;
  bool (*test)(const void* context, std::uint32_t i, std::uint32_t j) = nullptr;
};

struct PointSet {
  std::string_view name;
  int dimension = 3;
  double density = 0;                  // kg/m^3 (3D), kg/m^2 (2D): point masses rho V^i
  double horizon = 0;                  // delta; 0 for a rigid body (none of its own)
  double spacing = 0;                  // lattice spacing dx: bounds how densely its points can sit
  std::span<const Vec3> reference;     // X^i
  std::span<const Vec3> displacement;  // u^i
  std::span<const Vec3> velocity;      // v^i
  std::span<const double> volume;      // V^i (areas in 2D)
  std::span<Vec3> force_density;       // b^i, contact adds to it; empty in a read-only view
  BondQuery bonds;
  // A deformable body's bond families (bodies/bond_family.hpp: point i's partners are
  // family_neighbour[family_offset[i] .. family_offset[i + 1])) and one flag per stored bond,
  // 1 while intact: the neighbourhood that takes up a frictional contact's couple
  // (point_cluster.hpp). Empty for a rigid body and a view without bonds.
  std::span<const std::size_t> family_offset;
  std::span<const std::uint32_t> family_neighbour;
  std::span<const std::uint8_t> bond_intact;
  // A rigid body's spin: a contact at p moves with v^i + omega x (p - x^i), and a force applied
  // at p rather than at x^i adds (p - x^i) x F to `couple` (the torque the body's motion adds to
  // that of its point forces). Deformable points have no spin of their own.
  bool spins = false;
  Vec3 angular_velocity = Vec3::Zero();
  Vec3* couple = nullptr;
  // A rigid body's points move together: the mass a contact law meets is the body's (infinite
  // for an imposed motion). 0: each point's own rho V^i.
  double rigid_mass = 0;
  // Points whose own contact force (and energy share) this process computes, 1 each; the others
  // are partners only (a distributed run's contact ghosts: src/engine/contact_ghosts.hpp). Empty:
  // every point.
  std::span<const std::uint8_t> computed;
  // Of the computed points, those whose energy share this process books (empty: all of them): a
  // rigid body that every rank holds and computes whole is booked by one rank.
  std::span<const std::uint8_t> booked;

  std::size_t size() const { return reference.size(); }
  Vec3 position(std::size_t i) const { return reference[i] + displacement[i]; }
  double mass(std::size_t i) const { return rigid_mass > 0 ? rigid_mass : density * volume[i]; }
  // Velocity of the body's material at p, as carried by point i.
  Vec3 velocity_at(std::size_t i, const Vec3& p) const {
    return spins ? Vec3(velocity[i] + angular_velocity.cross(p - position(i))) : velocity[i];
  }
  bool computes(std::size_t i) const { return computed.empty() || computed[i] != 0; }
  bool books(std::size_t i) const { return booked.empty() ? computes(i) : booked[i] != 0; }
  bool bonded(std::uint32_t i, std::uint32_t j) const {
    return bonds.test != nullptr && bonds.test(bonds.context, i, j);
  }
};

}  // namespace ckpd
