// The keys of bodies in the key table (src/input/key_table.hpp): deformable bodies and their
// far field and point clouds, rigid bodies, their motion and mesh walls.
#include "src/input/key_table.hpp"

namespace ckpd {

namespace {

using K = ValueKind;

KeySpec name_key() {
  return {"name", K::text, "-", kRequired,
          "the body's name (conditions, contact and output use it)"};
}
KeySpec dimension_key() {
  return {"dimension", K::integer, "-", "3", "2 for a plane body, 3 for a solid", {}, "2 or 3"};
}
KeySpec max_points_key() {
  return {"max_points",
          K::integer,
          "-",
          "20000000",
          "the most points the body may have (a guard against a mistyped spacing)",
          {},
          "> 0"};
}
KeySpec geometry_key(const char* fallback, const char* meaning) {
  return {"geometry", K::section, "-", fallback, meaning, {}, "", "shape"};
}

KeySection body_section() {
  KeySection s{
      "body",
      "bodies entries (deformable)",
      "A peridynamic body: points on a lattice (or from a point cloud) with bonds within the "
      "horizon. A map with the key `rigid` is a rigid body instead.",
      {name_key(),
       {"material", K::text, "-", kRequired, "the name of a material in `materials`"},
       dimension_key(),
       {"plane",
        K::text,
        "-",
        "stress (2D only)",
        "the plane mode of a 2D body",
        {"stress", "strain"}},
       {"spacing", K::number, "m", kRequired, "the lattice spacing dx", {}, "1e-9 to 1e6"},
       {"horizon",
        K::number,
        "m",
        "give horizon or horizon_ratio",
        "the horizon delta",
        {},
        ">= spacing"},
       {"horizon_ratio",
        K::number,
        "-",
        "give horizon or horizon_ratio",
        "the horizon as a multiple of the spacing, delta / dx",
        {},
        ">= 1"},
       max_points_key(),
       geometry_key("give geometry or points", "the shape whose lattice sites are the points"),
       {"points",
        K::section,
        "-",
        "give geometry or points",
        "the points from a point-cloud file",
        {},
        "",
        "point_cloud"},
       {"beta",
        K::text,
        "-",
        "strict",
        "a point-cloud family fuller than the lattice's: strict refuses it, capped caps its "
        "weight at 1",
        {"strict", "capped"}},
       {"degenerate_fraction",
        K::number,
        "-",
        "1e-10",
        "triangles (tetrahedra) of area below f L^2 (volume below f L^3) are left out",
        {},
        "(0, 1)"},
       {"inversion_penalty",
        K::number,
        "-",
        "0",
        "energy penalty factor on inverted triangles and tetrahedra (0: off, 1: signed volume)",
        {},
        ">= 0"},
       {"damage_rule",
        K::text,
        "-",
        "all_edges (model ckpd), centre_bonds (other models)",
        "which failed bonds switch a triangle or tetrahedron off",
        {"all_edges", "centre_bonds"}},
       {"force_form",
        K::text,
        "-",
        "energy_consistent (model ckpd), own_family (other models)",
        "how the CKPD forces follow from the energy (other models: own_family only)",
        {"energy_consistent", "own_family"}},
       {"far_field",
        K::section,
        "-",
        "off",
        "undamaged points whose bonds barely change take the linear operator's force",
        {},
        "",
        "far_field"},
       {"lattice_stencil", K::boolean, "-", "true",
        "use the lattice stencil when the points form a lattice (false: the general kernel)"},
       {"constants",
        K::text,
        "-",
        "analytic",
        "the CKPD constants: analytic, or calibrated to the lattice's patch test",
        {"analytic", "calibrated"}},
       {"precracks", K::polygons, "m", "none",
        "cracks whose crossing bonds start failed: a segment [[x, y], [x, y]] in 2D, a planar "
        "polygon of 3 or more corners in 3D"},
       {"no_failure",
        K::sections,
        "-",
        "none",
        "regions whose points' bonds never fail",
        {},
        "",
        "shape"}}};
  s.alternative_key = "rigid";
  s.alternative = "rigid_body";
  s.exactly_one = {{"horizon", "horizon_ratio"}, {"geometry", "points"}};
  return s;
}

const bool body_registered = register_key_section(body_section());

const bool far_field_registered = register_key_section(
    {"far_field",
     "far_field",
     "Points whose family is undamaged and whose bond vectors change by less than tolerance x "
     "their length take the linear operator's force.",
     {{"tolerance",
       K::number,
       "-",
       kRequired,
       "the largest relative bond-vector change of a linear point (0: off)",
       {},
       ">= 0"},
      {"corotated", K::boolean, "-", "false",
       "measure the change once the family's rotation is taken out"}}});

const bool point_cloud_registered = register_key_section(
    {"point_cloud",
     "points",
     "A body's points from a CSV file: a header naming the columns (x,y,volume in 2D, "
     "x,y,z,volume in 3D), then one point per line.",
     {{"file", K::text, "-", kRequired, "the CSV file (relative to the case file's folder)"},
      {"format", K::text, "-", "csv", "the file's format", {"csv"}}}});

KeySection rigid_body_section() {
  KeySection s{
      "rigid_body",
      "bodies entries (rigid)",
      "A body that moves as a whole: points on a lattice (geometry), a triangle surface "
      "(mesh_wall) or a DEM sphere (dem_sphere); it has no bonds.",
      {name_key(),
       {"material", K::text, "-", "none",
        "a material in `materials` giving the density (and E, nu for contact laws that use them)"},
       dimension_key(),
       {"rigid", K::section, "-", kRequired, "the body's motion", {}, "", "rigid"},
       {"mesh_wall",
        K::section,
        "-",
        "give geometry, mesh_wall or dem_sphere",
        "a triangle surface as the body (3D)",
        {},
        "",
        "mesh_wall"},
       {"dem_sphere",
        K::section,
        "-",
        "give geometry, mesh_wall or dem_sphere",
        "a DEM sphere: one point with the solid sphere's inertia, touching at its radius",
        {},
        "",
        "dem_sphere"},
       {"spacing",
        K::number,
        "m",
        "required with geometry",
        "the lattice spacing of its points",
        {},
        "1e-9 to 1e6"},
       max_points_key(),
       geometry_key("give geometry, mesh_wall or dem_sphere",
                    "the shape whose lattice sites are the points")}};
  s.refuses_keys_of = "body";
  s.exactly_one = {{"geometry", "mesh_wall", "dem_sphere"}};
  return s;
}

const bool rigid_body_registered = register_key_section(rigid_body_section());

const bool rigid_registered = register_key_section(
    {"rigid",
     "rigid",
     "A rigid body's motion: prescribed (it keeps its velocities) or free (contact and loads move "
     "it).",
     {{"motion", K::text, "-", kRequired, "prescribed or free", {"prescribed", "free"}},
      {"velocity",
       K::vector,
       "m/s",
       "0",
       "the velocity (a free body's initial one)",
       {},
       "below the speed of light"},
      {"angular_velocity", K::number_or_vector, "rad/s", "0",
       "the angular velocity (a number, about z, in 2D)"},
      {"mass",
       K::number,
       "kg",
       "the material's density x the volume",
       "the mass (give it or a material, not both; a free body needs one)",
       {},
       "> 0"},
      {"density",
       K::number,
       "kg/m^3",
       "the material's",
       "the density (instead of mass or a material)",
       {},
       "1e-6 to 1e6"},
      {"youngs_modulus",
       K::number,
       "Pa",
       "the material's",
       "E for contact laws that use it (with poisson_ratio, instead of a material)",
       {},
       "1e-3 to 1e16"},
      {"poisson_ratio",
       K::number,
       "-",
       "the material's",
       "nu for contact laws that use it (with youngs_modulus)",
       {},
       "(-1, 0.5)"}}});

const bool dem_sphere_registered = register_key_section(
    {"dem_sphere",
     "dem_sphere",
     "A DEM sphere as LIGGGHTS and YADE have it: a rigid body of one point at its centre, with the "
     "mass rho 4/3 pi R^3 (or rigid.mass) and the solid sphere's inertia 2/5 m R^2; it touches "
     "another sphere at R_a + R_b, a mesh wall at R and a point of a lattice body at R plus half "
     "that body's own contact radius.",
     {{"center", K::vector, "m", kRequired, "the centre"},
      {"radius", K::number, "m", kRequired, "the radius R", {}, "1e-9 to 1e6"}}});

}  // namespace

}  // namespace ckpd
