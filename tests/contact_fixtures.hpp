#pragma once
// Scenes for the contact tests: small steel spheres (m = 2.015, nu = 0.25: bonds only, which is
// cheap) written as case files, and the sums the tests compare against.
#include <sstream>
#include <string>

#include "run_helpers.hpp"
#include "src/case/case_loader.hpp"
#include "src/engine/simulation.hpp"

namespace ckpd::testing {

inline Scene scene_from_text(const std::string& tag, const std::string& text) {
  const auto dir = fresh_dir(tag);
  return load_scene(write_file(dir / "case.yaml", text));
}

// `{name: NAME, material: M, geometry: sphere at (x, y, z) radius r, spacing dx, m = 2.015}`
inline std::string sphere_body(const std::string& name, const std::string& material, double x,
                               double y, double z, double radius, double spacing) {
  std::ostringstream s;
  s.precision(17);
  s << "  - {name: " << name << ", material: " << material << ", geometry: {type: sphere, center: ["
    << x << ", " << y << ", " << z << "], radius: " << radius << "}, spacing: " << spacing
    << ", horizon_ratio: 2.015}\n";
  return s.str();
}

inline Vec3 momentum(const Body& b) {
  Vec3 p = Vec3::Zero();
  for (std::size_t i = 0; i < b.size(); ++i) p += b.density * b.volume[i] * b.velocity[i];
  return p;
}

inline Vec3 centre_of_mass(const Body& b) {
  Vec3 c = Vec3::Zero();
  double m = 0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    c += b.volume[i] * b.current_position(i);
    m += b.volume[i];
  }
  return c / m;
}

// Sum over points of rho V |v|: the scale against which momentum errors are relative.
inline double momentum_scale(const Scene& scene) {
  double s = 0;
  for (const SceneBody& sb : scene.bodies)
    for (std::size_t i = 0; i < sb.body.size(); ++i)
      s += sb.body.density * sb.body.volume[i] * sb.body.velocity[i].norm();
  return s;
}

}  // namespace ckpd::testing
