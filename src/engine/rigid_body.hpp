#pragma once
// Rigid bodies: impactors, supports and free rigid bodies. Their points (a Body without bonds)
// carry positions and velocities for contact, energies and output; the motion is one rigid
// motion x^i = c + R (X^i - c0), either imposed (a constant translation and rotation velocity:
// an indenter; zero for a fixed support) or integrated from the total force and torque of the
// loads and contacts on its points, in the velocity-Verlet pattern of the deformable bodies:
//
//   v += dt/2 F/M,  L += dt/2 tau;  c += dt v,  R <- rot(dt omega) R with omega = I(R)^-1 L;
//   forces at t + dt;  v += dt/2 F/M,  L += dt/2 tau.
//
// L is the angular momentum about the centre of mass in world axes and I(R) = R I0 R^T. The
// rotation step is exact for a constant omega; for a body whose inertia is not isotropic omega
// changes within the step and the update is first-order accurate in that change (second order
// overall for spheres and cubes, which is what the cases use).
#include <Eigen/Geometry>

#include "bodies/body.hpp"

namespace ckpd {

class RigidMotion {
 public:
  enum class Kind { prescribed, free };
  using Mat3 = Eigen::Matrix3d;

  // Mass properties from the points (mass rho V^i each); the body must have a positive density
  // for a free motion. `velocity` is that of the centre of mass, `angular_velocity` about it.
  RigidMotion(const Body& body, Kind kind, const Vec3& velocity, const Vec3& angular_velocity);
  // The same with the inertia about the centre given (reference axes) rather than summed from the
  // points: a DEM sphere is one point with the solid sphere's 2/5 m R^2
  // (src/case/rigid_body_loader.cpp).
  RigidMotion(const Body& body, Kind kind, const Vec3& velocity, const Vec3& angular_velocity,
              const Mat3& inertia);

  Kind kind() const { return kind_; }
  bool prescribed() const { return kind_ == Kind::prescribed; }
  double mass() const { return mass_; }
  const Vec3& centre() const { return centre_; }
  const Vec3& velocity() const { return velocity_; }
  Vec3 angular_velocity() const;
  // Speed of the fastest point now.
  double max_speed(const Body& body) const;
  // The kinetic energy of the spin that the point velocities do not carry: with a given inertia,
  // 1/2 omega . (I - I_points) omega (a DEM sphere's whole 1/2 I omega^2); 0 otherwise.
  double spin_energy_beyond_points() const;

  // Point velocities (and displacements) at t = 0.
  void initialise(Body& body) const;
  // From t to t + dt: kick with the forces on the points (free), move every point. Leaves each
  // point's velocity at its displacement increment / dt (the midpoint velocity the work
  // bookkeeping uses).
  void first_half(Body& body, double t, double dt);
  // After the forces at t + dt: kick (free) and set the point velocities at t + dt.
  void second_half(Body& body, double t, double dt);
  // Point accelerations after a force evaluation. Prescribed: the exact ones of the imposed
  // motion. Free: b^i / rho, so that the engine's work increment V (rho a - (b - b_ext)) . du
  // books only the external loads: the internal forces that keep a rigid body rigid do no work.
  void set_accelerations(Body& body, double t) const;

  // A torque on the body besides that of its point forces about the centre: contact forces
  // that act at a contact point rather than at the point carrying them (contact/point_set.hpp).
  // Cleared with the point forces before every force evaluation, used by the next two kicks.
  Vec3* couple() { return &couple_; }
  void clear_couple() { couple_ = Vec3::Zero(); }

  // The motion's state between steps, for checkpoints.
  struct State {
    Vec3 centre, velocity, angular_momentum;
    Eigen::Quaterniond orientation;
    Vec3 couple = Vec3::Zero();
  };
  State state() const { return {centre_, velocity_, angular_momentum_, orientation_, couple_}; }
  void restore(const State& s) {
    centre_ = s.centre;
    velocity_ = s.velocity;
    angular_momentum_ = s.angular_momentum;
    orientation_ = s.orientation;
    couple_ = s.couple;
  }

 private:
  Vec3 force(const Body& body) const;
  Vec3 torque(const Body& body) const;
  void set_up(const Body& body, const Vec3& angular_velocity);
  Mat3 rotation() const { return orientation_.toRotationMatrix(); }
  void place_points(Body& body) const;
  void set_point_velocities(Body& body) const;

  Kind kind_;
  double mass_ = 0;
  Vec3 reference_centre_ = Vec3::Zero();  // c0
  Mat3 inverse_inertia_ = Mat3::Zero();   // I0^-1 (pseudo-inverse for points on a line)
  Mat3 inertia_ = Mat3::Zero();           // I0 about c0, reference axes
  Mat3 point_inertia_ = Mat3::Zero();     // that of the points (I0 unless it was given)
  bool inertia_given_ = false;
  Vec3 centre_ = Vec3::Zero();
  Vec3 velocity_ = Vec3::Zero();
  Eigen::Quaterniond orientation_ = Eigen::Quaterniond::Identity();
  Vec3 angular_momentum_ = Vec3::Zero();          // world axes (free)
  Vec3 imposed_angular_velocity_ = Vec3::Zero();  // prescribed
  Vec3 couple_ = Vec3::Zero();
  std::vector<Vec3> previous_displacement_;  // scratch of first_half
};

// A body of points without bonds (no families, no interaction counts): what a rigid body needs.
// Throws std::invalid_argument for an empty set or a non-positive volume.
Body make_point_set(std::string name, int dimension, std::vector<Vec3> position,
                    std::vector<double> volume, double density);

}  // namespace ckpd
