#include "src/engine/rigid_body.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <stdexcept>

namespace ckpd {

Body make_point_set(std::string name, int dimension, std::vector<Vec3> position,
                    std::vector<double> volume, double density) {
  if (position.empty()) throw std::invalid_argument("rigid body '" + name + "' has no points");
  for (double v : volume)
    if (!(v > 0))
      throw std::invalid_argument("rigid body '" + name + "' has a non-positive volume");
  Body body;
  body.name = std::move(name);
  body.dimension = dimension;
  body.density = density;
  body.horizon = 0;  // none: contact uses the partner's (contact_law.hpp)
  const std::size_t n = position.size();
  body.reference_position = std::move(position);
  body.volume = std::move(volume);
  body.family.offset.assign(n + 1, 0);
  body.beta.assign(n, 0);
  body.dv1.assign(n, 0);
  body.dv2.assign(n, 0);
  body.dv3.assign(n, 0);
  body.n2.assign(n, 0);
  body.n3.assign(n, 0);
  body.stiffness_bound.assign(n, 0);
  body.displacement.assign(n, Vec3::Zero());
  body.velocity.assign(n, Vec3::Zero());
  body.acceleration.assign(n, Vec3::Zero());
  body.external_force_density.assign(n, Vec3::Zero());
  body.force_density.assign(n, Vec3::Zero());
  body.strain_energy_density.assign(n, 0.0);
  return body;
}

RigidMotion::RigidMotion(const Body& body, Kind kind, const Vec3& velocity,
                         const Vec3& angular_velocity)
    : kind_(kind), velocity_(velocity) {
  set_up(body, angular_velocity);
}

RigidMotion::RigidMotion(const Body& body, Kind kind, const Vec3& velocity,
                         const Vec3& angular_velocity, const Mat3& inertia)
    : kind_(kind), velocity_(velocity), inertia_(inertia), inertia_given_(true) {
  set_up(body, angular_velocity);
}

void RigidMotion::set_up(const Body& body, const Vec3& angular_velocity) {
  // The centre is the volume centroid, which is the mass centre for the uniform density and
  // the pivot of a prescribed rotation.
  double volume = 0;
  for (std::size_t i = 0; i < body.size(); ++i) {
    volume += body.volume[i];
    reference_centre_ += body.volume[i] * body.reference_position[i];
  }
  reference_centre_ /= volume;
  centre_ = reference_centre_;
  mass_ = body.density * volume;
  for (std::size_t i = 0; i < body.size(); ++i) {
    const Vec3 r = body.reference_position[i] - reference_centre_;
    point_inertia_ +=
        body.density * body.volume[i] * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
  }
  if (!inertia_given_) inertia_ = point_inertia_;
  if (kind_ == Kind::free) {
    if (!(mass_ > 0))
      throw std::invalid_argument("free rigid body '" + body.name + "' has no mass");
    // Pseudo-inverse: a body whose points lie on a line has no inertia about it and does not
    // spin about it.
    Eigen::SelfAdjointEigenSolver<Mat3> eig(inertia_);
    const double largest = eig.eigenvalues().maxCoeff();
    Vec3 inverse = Vec3::Zero();
    for (int k = 0; k < 3; ++k)
      if (eig.eigenvalues()[k] > 1e-12 * largest) inverse[k] = 1 / eig.eigenvalues()[k];
    inverse_inertia_ = eig.eigenvectors() * inverse.asDiagonal() * eig.eigenvectors().transpose();
    angular_momentum_ = inertia_ * angular_velocity;
  } else {
    imposed_angular_velocity_ = angular_velocity;
  }
}

double RigidMotion::spin_energy_beyond_points() const {
  if (!inertia_given_) return 0;
  const Mat3 R = rotation();
  const Vec3 w = R.transpose() * angular_velocity();  // reference axes
  return 0.5 * w.dot((inertia_ - point_inertia_) * w);
}

Vec3 RigidMotion::angular_velocity() const {
  if (kind_ == Kind::prescribed) return imposed_angular_velocity_;
  const Mat3 R = rotation();
  return R * (inverse_inertia_ * (R.transpose() * angular_momentum_));
}

double RigidMotion::max_speed(const Body& body) const {
  const Vec3 omega = angular_velocity();
  double fastest = 0;
  for (std::size_t i = 0; i < body.size(); ++i)
    fastest =
        std::max(fastest, (velocity_ + omega.cross(body.current_position(i) - centre_)).norm());
  return fastest;
}

Vec3 RigidMotion::force(const Body& body) const {
  Vec3 f = Vec3::Zero();
  for (std::size_t i = 0; i < body.size(); ++i) f += body.volume[i] * body.force_density[i];
  return f;
}

Vec3 RigidMotion::torque(const Body& body) const {
  Vec3 t = couple_;
  for (std::size_t i = 0; i < body.size(); ++i)
    t += (body.current_position(i) - centre_).cross(body.volume[i] * body.force_density[i]);
  return t;
}

void RigidMotion::place_points(Body& body) const {
  const Mat3 R = rotation();
  for (std::size_t i = 0; i < body.size(); ++i) {
    const Vec3& X = body.reference_position[i];
    body.displacement[i] = centre_ + R * (X - reference_centre_) - X;
  }
}

void RigidMotion::set_point_velocities(Body& body) const {
  const Vec3 omega = angular_velocity();
  for (std::size_t i = 0; i < body.size(); ++i)
    body.velocity[i] = velocity_ + omega.cross(body.current_position(i) - centre_);
}

void RigidMotion::initialise(Body& body) const {
  place_points(body);
  set_point_velocities(body);
}

void RigidMotion::first_half(Body& body, double t, double dt) {
  previous_displacement_ = body.displacement;
  if (kind_ == Kind::free) {
    velocity_ += 0.5 * dt / mass_ * force(body);
    angular_momentum_ += 0.5 * dt * torque(body);
    const Vec3 omega = angular_velocity();
    centre_ += dt * velocity_;
    const double angle = omega.norm() * dt;
    if (angle > 0) {
      orientation_ =
          Eigen::Quaterniond(Eigen::AngleAxisd(angle, omega.normalized())) * orientation_;
      orientation_.normalize();
    }
  } else {
    // Imposed: the exact pose at t + dt.
    centre_ = reference_centre_ + (t + dt) * velocity_;
    const double angle = imposed_angular_velocity_.norm() * (t + dt);
    orientation_ =
        angle > 0
            ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, imposed_angular_velocity_.normalized()))
            : Eigen::Quaterniond::Identity();
  }
  place_points(body);
  for (std::size_t i = 0; i < body.size(); ++i)
    body.velocity[i] = (body.displacement[i] - previous_displacement_[i]) / dt;
}

void RigidMotion::second_half(Body& body, double /*t*/, double dt) {
  if (kind_ == Kind::free) {
    velocity_ += 0.5 * dt / mass_ * force(body);
    angular_momentum_ += 0.5 * dt * torque(body);
  }
  set_point_velocities(body);
}

void RigidMotion::set_accelerations(Body& body, double /*t*/) const {
  if (kind_ == Kind::free) {
    const double inv_rho = 1 / body.density;
    for (std::size_t i = 0; i < body.size(); ++i)
      body.acceleration[i] = inv_rho * body.force_density[i];
    return;
  }
  const Vec3 omega = imposed_angular_velocity_;
  for (std::size_t i = 0; i < body.size(); ++i)
    body.acceleration[i] = omega.cross(omega.cross(body.current_position(i) - centre_));
}

}  // namespace ckpd
