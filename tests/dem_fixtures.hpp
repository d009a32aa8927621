#pragma once
// Scenes for the DEM contact-law tests, built in code: rigid bodies of a few points (a DEM
// sphere is one point; a spinning sphere a small lattice ball whose only lowest point meets the
// wall), a fixed flat mesh wall z = 0, a uniform body force, and the laws' settings.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "contact/mesh_wall.hpp"
#include "src/engine/simulation.hpp"

namespace ckpd::testing {

inline constexpr double kDemDensity = 7850;

// A rigid body of the given points (volume `volume` each) moving at `velocity`.
inline SceneBody rigid_points(const std::string& name, std::vector<Vec3> points, double volume,
                              const Vec3& velocity, double spacing = 0,
                              RigidMotion::Kind kind = RigidMotion::Kind::free,
                              const Vec3& spin = Vec3::Zero()) {
  SceneBody sb;
  const std::size_t n = points.size();
  sb.body = make_point_set(name, 3, std::move(points), std::vector<double>(n, volume), kDemDensity);
  sb.spacing = spacing;
  sb.rigid.emplace(sb.body, kind, velocity, spin);
  return sb;
}

// Lattice points (spacing dx) within `radius` of `centre`, radius a multiple of dx: one point
// at the bottom pole, the next ones a whole dx above it.
inline std::vector<Vec3> lattice_ball(const Vec3& centre, double radius, double dx) {
  std::vector<Vec3> p;
  const int n = static_cast<int>(std::round(radius / dx));
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int k = -n; k <= n; ++k)
        if (i * i + j * j + k * k <= n * n) p.push_back(centre + dx * Vec3(i, j, k));
  return p;
}

// A fixed square wall in the plane z = 0, outward normal +z, half-width `half`.
inline SceneBody flat_wall(double half) {
  std::vector<Vec3> v{{-half, -half, 0}, {half, -half, 0}, {half, half, 0}, {-half, half, 0}};
  std::vector<std::array<std::uint32_t, 3>> t{{0, 1, 2}, {0, 2, 3}};
  WallCarriers carriers;
  carriers.centre = Vec3::Zero();
  carriers.half_length = Vec3(half, half, 0);
  SceneBody sb;
  sb.body = make_point_set("wall", 3, carriers.points(), std::vector<double>(6, 1.0 / 6), 1.0);
  sb.rigid.emplace(sb.body, RigidMotion::Kind::prescribed, Vec3::Zero(), Vec3::Zero());
  sb.wall = std::make_shared<const MeshWall>(v, t, carriers);
  return sb;
}

// A uniform acceleration g on every point (gravity along any direction).
class UniformAcceleration : public Condition {
 public:
  UniformAcceleration(const Body& body, const Vec3& g) : g_(g) {
    for (std::uint32_t i = 0; i < body.size(); ++i) points_.push_back(i);
  }
  void add_external_force(Body& b, double) const override {
    for (std::uint32_t i : points_) b.external_force_density[i] += b.density * g_;
  }

 private:
  Vec3 g_;
};

// A global law for every pair: `law` with its parameters, l_c, and (for laws with a spring
// from Ccon) a stiffness and horizon.
inline ContactSettings dem_settings(const std::string& law,
                                    std::map<std::string, std::vector<double>> parameters,
                                    double radius, double stiffness = 0, double horizon = 0) {
  ContactSettings s;
  s.present = true;
  s.global.law = law;
  s.global.parameters = std::move(parameters);
  s.global.radius = radius;
  if (stiffness > 0) s.global.stiffness = stiffness;
  if (horizon > 0) s.global.horizon = horizon;
  return s;
}

// Ccon that gives a linear_dashpot spring k = c V^i V^j between points of volume v, horizon h.
inline double ccon_for_spring(double k, double v, double h) {
  return k * M_PI * std::pow(h, 5) / (9 * v * v);
}

inline Scene dem_scene(std::vector<SceneBody> bodies, ContactSettings contact, double dt,
                       long long steps) {
  Scene scene;
  scene.case_file = "dem_scene";
  scene.bodies = std::move(bodies);
  scene.contact = std::move(contact);
  scene.time.dt = dt;
  scene.time.steps = steps;
  return scene;
}

}  // namespace ckpd::testing
