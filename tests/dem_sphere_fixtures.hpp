#pragma once
// Case text for the DEM sphere tests (src/case/rigid_body_loader.cpp): spheres given by their
// own density, E and nu (no `materials` section), a square mesh wall z = 0 written next to the
// case, and the state of a sphere after a run.
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <string>

#include "run_helpers.hpp"
#include "src/engine/simulation.hpp"

namespace ckpd::testing {

// Glass: the sphere of cases/dem_sphere_oblique.yaml.
inline constexpr double kGlassDensity = 2500, kGlassModulus = 70e9, kGlassPoisson = 0.25;

inline std::string yaml_vector(const Vec3& v) {
  std::ostringstream s;
  s << std::setprecision(17) << '[' << v.x() << ", " << v.y() << ", " << v.z() << ']';
  return s.str();
}

// One `bodies` entry: a free DEM sphere of glass (or `density`) at `centre`.
inline std::string dem_sphere_entry(const std::string& name, const Vec3& centre, double radius,
                                    const Vec3& velocity, const Vec3& spin = Vec3::Zero(),
                                    double density = kGlassDensity) {
  std::ostringstream s;
  s << std::setprecision(17) << "  - {name: " << name
    << ", rigid: {motion: free, velocity: " << yaml_vector(velocity)
    << ", angular_velocity: " << yaml_vector(spin) << ", density: " << density
    << ", youngs_modulus: " << kGlassModulus << ", poisson_ratio: " << kGlassPoisson
    << "}, dem_sphere: {center: " << yaml_vector(centre) << ", radius: " << radius << "}}\n";
  return s.str();
}

// A fixed glass mesh wall: the square |x|, |y| < half in the plane z = 0, facing +z, written to
// dir/floor.obj.
inline std::string glass_floor_entry(const std::filesystem::path& dir, double half = 0.02) {
  std::ostringstream obj;
  obj << std::setprecision(17) << "v " << -half << ' ' << -half << " 0\nv " << half << ' ' << -half
      << " 0\nv " << half << ' ' << half << " 0\nv " << -half << ' ' << half
      << " 0\nf 1 2 3\nf 1 3 4\n";
  write_file(dir / "floor.obj", obj.str());
  std::ostringstream s;
  s << "  - {name: floor, rigid: {motion: prescribed, youngs_modulus: " << kGlassModulus
    << ", poisson_ratio: " << kGlassPoisson << "}, mesh_wall: {file: floor.obj}}\n";
  return s.str();
}

// hertz_mindlin with restitution e and friction mu for every pair.
inline std::string hertz_mindlin_contact(double e, double mu) {
  std::ostringstream s;
  s << std::setprecision(17) << "contact: {law: hertz_mindlin, restitution: " << e
    << ", friction: " << mu << "}\n";
  return s.str();
}

// Advances until the bodies have touched and then parted (or the planned steps end); returns
// whether they touched.
inline bool run_through_contact(Simulation& sim) {
  bool met = false;
  while (sim.step() < sim.planned_steps()) {
    sim.advance(false);
    const bool now = sim.contact()->statistics().points_in_contact > 0;
    if (met && !now) break;
    met = met || now;
  }
  return met;
}

}  // namespace ckpd::testing
