#pragma once
// The total linear and angular momentum (about the origin) of a scene's moving bodies, formed
// from what each body's motion is, not from the integrator's own momentum state: a deformable
// body's points (sum m v, sum x x m v); a free rigid body's centre (m v, c x m v) plus its spin,
// I omega = 2/5 m R^2 omega for a DEM sphere and its points' sum (x - c) x m (v - v_c)
// otherwise. A prescribed rigid body takes up any impulse, so it is left out. The scales are
// the sums of the terms' magnitudes, for relative errors.
#include <cstddef>

#include "src/engine/simulation.hpp"

namespace ckpd::testing {

struct SceneMomentum {
  Vec3 linear = Vec3::Zero(), angular = Vec3::Zero();
  double linear_scale = 0, angular_scale = 0;
};

inline SceneMomentum scene_momentum(const Scene& scene) {
  SceneMomentum m;
  for (const SceneBody& sb : scene.bodies) {
    const Body& b = sb.body;
    if (sb.rigid) {
      const RigidMotion& r = *sb.rigid;
      if (r.prescribed()) continue;
      const Vec3 p = r.mass() * r.velocity();
      Vec3 spin = Vec3::Zero();
      if (sb.sphere_radius > 0)
        spin = 0.4 * r.mass() * sb.sphere_radius * sb.sphere_radius * r.angular_velocity();
      else
        for (std::size_t i = 0; i < b.size(); ++i)
          spin += (b.current_position(i) - r.centre())
                      .cross(b.density * b.volume[i] * (b.velocity[i] - r.velocity()));
      const Vec3 orbit = r.centre().cross(p);
      m.linear += p;
      m.angular += orbit + spin;
      m.linear_scale += p.norm();
      m.angular_scale += orbit.norm() + spin.norm();
      continue;
    }
    for (std::size_t i = 0; i < b.size(); ++i) {
      const Vec3 p = b.density * b.volume[i] * b.velocity[i];
      const Vec3 x = b.current_position(i);
      m.linear += p;
      m.angular += x.cross(p);
      m.linear_scale += p.norm();
      m.angular_scale += x.norm() * p.norm();
    }
  }
  return m;
}

}  // namespace ckpd::testing
