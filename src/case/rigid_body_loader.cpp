#include "src/case/rigid_body_loader.hpp"

#include <numbers>

#include "src/case/mesh_wall_loader.hpp"
#include "src/geometry/lattice.hpp"
#include "src/geometry/mesh/mesh_shape.hpp"
#include "src/geometry/shape.hpp"

namespace ckpd {

namespace {

constexpr std::size_t kDefaultMaxPoints = 20'000'000;

// One point at the centre carrying the sphere's volume 4/3 pi R^3 (so rho V is its mass) and
// the solid sphere's inertia 2/5 m R^2 about every axis.
SceneBody read_dem_sphere(const CaseNode& d, const std::string& name, RigidMotion::Kind kind,
                          const Vec3& velocity, const Vec3& omega, std::optional<double> mass,
                          std::optional<double> density) {
  const Vec3 centre = d.required("center").as_vector(3);
  const double radius = d.required("radius").as_in_range(1e-9, 1e6, "a sphere radius in m");
  d.finish();
  const double volume = 4.0 / 3 * std::numbers::pi * radius * radius * radius;
  // A prescribed sphere without a mass books no kinetic energy; its motion needs none.
  const double rho = mass ? *mass / volume : density.value_or(0.0);
  SceneBody sb;
  sb.sphere_radius = radius;
  try {
    sb.body = make_point_set(name, 3, {centre}, {volume}, rho);
    const double inertia = 0.4 * rho * volume * radius * radius;
    sb.rigid.emplace(sb.body, kind, velocity, omega,
                     RigidMotion::Mat3(inertia * RigidMotion::Mat3::Identity()));
  } catch (const std::invalid_argument& e) {
    throw CaseError(d.where() + ": " + e.what());
  }
  return sb;
}

}  // namespace

SceneBody read_rigid_body(const CaseNode& n, std::optional<double> material_density,
                          std::optional<ElasticConstants> material_elastic) {
  const std::string name = n.required("name").as_string();
  int dimension = 3;
  if (auto d = n.optional("dimension")) {
    dimension = static_cast<int>(d->as_integer());
    if (dimension != 2 && dimension != 3) d->fail("2 or 3");
  }
  for (const char* bonded : {"horizon", "horizon_ratio", "precracks", "no_failure", "plane"})
    if (n.has(bonded))
      n.required(bonded).fail(std::string("no `") + bonded + "` on a rigid body (it has no bonds)");

  const CaseNode r = n.required("rigid");
  const CaseNode motion_node = r.required("motion");
  const std::string motion = motion_node.as_string();
  if (motion != "prescribed" && motion != "free") motion_node.fail("'prescribed' or 'free'");
  const RigidMotion::Kind kind =
      motion == "free" ? RigidMotion::Kind::free : RigidMotion::Kind::prescribed;
  Vec3 velocity = Vec3::Zero(), omega = Vec3::Zero();
  if (auto v = r.optional("velocity"))
    velocity = v->as_vector_below(dimension, CaseNode::kMaxSpeed, "a velocity in m/s");
  if (auto w = r.optional("angular_velocity"))
    omega = dimension == 3 ? w->as_vector(3) : Vec3(0, 0, w->as_double());
  std::optional<double> mass;
  if (auto m = r.optional("mass")) mass = m->as_positive();
  if (auto d = r.optional("density")) {
    if (mass) d->fail("either rigid.mass or rigid.density, not both");
    if (material_density) d->fail("either rigid.density or a material (its density), not both");
    material_density = d->as_in_range(1e-6, 1e6, "a density in kg/m^3");
  }
  if (mass && material_density)
    r.required("mass").fail("either rigid.mass or a material (its density), not both");
  if (kind == RigidMotion::Kind::free && !mass && !material_density)
    r.fail(
        "a mass for a free rigid body: rigid.mass (kg), rigid.density (kg/m^3) or a material (its "
        "density)");
  // E and nu for contact laws that use them (hertz_mindlin): both keys or neither.
  std::optional<ElasticConstants> elastic = material_elastic;
  if (r.has("youngs_modulus") || r.has("poisson_ratio")) {
    if (material_elastic)
      r.required(r.has("youngs_modulus") ? "youngs_modulus" : "poisson_ratio")
          .fail(
              "either rigid.youngs_modulus and rigid.poisson_ratio or a material (its E and "
              "nu), not both");
    ElasticConstants c;
    c.youngs_modulus =
        r.required("youngs_modulus").as_in_range(1e-3, 1e16, "a Young's modulus in Pa");
    const CaseNode nu = r.required("poisson_ratio");
    c.poisson_ratio = nu.as_double();
    if (!(c.poisson_ratio > -1 && c.poisson_ratio < 0.5)) nu.fail("a Poisson's ratio in (-1, 0.5)");
    elastic = c;
  }
  r.finish();
  if (auto d = n.optional("dem_sphere")) {
    for (const char* other : {"geometry", "mesh_wall", "spacing", "max_points"})
      if (n.has(other))
        n.required(other).fail(std::string("no `") + other +
                               "` on a DEM sphere (its `dem_sphere` gives its centre and radius)");
    if (dimension != 3) d->fail("a 3D body for a DEM sphere");
    SceneBody sphere = read_dem_sphere(*d, name, kind, velocity, omega, mass, material_density);
    sphere.elastic = elastic;
    n.finish();
    return sphere;
  }
  if (auto w = n.optional("mesh_wall")) {
    if (n.has("geometry")) n.fail("either geometry (points) or mesh_wall (a surface), not both");
    if (dimension != 3) w->fail("a 3D body for a mesh wall");
    SceneBody wall = read_mesh_wall(n, *w, name, kind, velocity, omega, mass, material_density);
    wall.elastic = elastic;
    return wall;
  }

  const double spacing = n.required("spacing").as_in_range(1e-9, 1e6, "a spacing in m");
  std::size_t max_points = kDefaultMaxPoints;
  if (auto m = n.optional("max_points")) {
    const long long v = m->as_integer();
    if (v <= 0) m->fail("a positive point limit");
    max_points = static_cast<std::size_t>(v);
  }
  const CaseNode geometry = n.required("geometry");
  const std::unique_ptr<Shape> shape = make_shape(geometry, dimension);
  LatticeSample sample;
  try {
    // The horizon only sizes the family-volume count, which a rigid body does not use.
    sample = sample_lattice(*shape, dimension, spacing, spacing, max_points);
  } catch (const std::invalid_argument& e) {
    geometry.fail(std::string("a geometry that can be sampled (") + e.what() + ")");
  }
  if (sample.position.empty())
    throw CaseError(geometry.where() + ": rigid body '" + name +
                    "' has no points: the geometry holds no lattice site at spacing " +
                    std::to_string(spacing) + " m");
  n.finish();

  double volume = 0;
  for (double v : sample.volume) volume += v;
  // A prescribed body without a mass books no kinetic energy; its motion needs none.
  const double density = mass ? *mass / volume : material_density.value_or(0.0);
  SceneBody sb;
  sb.spacing = spacing;
  sb.elastic = elastic;
  try {
    sb.body = make_point_set(name, dimension, std::move(sample.position), std::move(sample.volume),
                             density);
    sb.rigid.emplace(sb.body, kind, velocity, omega);
    if (const auto* m = dynamic_cast<const MeshShape*>(shape.get())) sb.mesh = m->info();
  } catch (const std::invalid_argument& e) {
    throw CaseError(n.where() + ": " + e.what());
  }
  return sb;
}

}  // namespace ckpd
