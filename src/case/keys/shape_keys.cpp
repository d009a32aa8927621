// The keys of shapes (a body's geometry, the regions of conditions, no-failure zones and
// outputs) and of mesh files in the key table (src/input/key_table.hpp): one variant per shape
// type of src/geometry/shapes.cpp and src/geometry/mesh/mesh_shape.cpp.
#include "src/input/key_table.hpp"

namespace ckpd {

namespace {

using K = ValueKind;

// The keys of a mesh file and its placement (src/geometry/mesh/mesh_source.cpp).
std::vector<KeySpec> mesh_file_keys() {
  return {{"file", K::text, "-", kRequired,
           "a triangle-mesh file (STL, OBJ, PLY, ...), relative to the case file's folder"},
          {"scale", K::number, "-", "1", "the factor from the file's units to m", {}, "> 0"},
          {"rotation",
           K::section,
           "-",
           "none",
           "a rotation about the origin, after the scale",
           {},
           "",
           "rotation"},
          {"translation", K::vector3, "m", "[0, 0, 0]", "a shift, after the rotation"}};
}

const bool shape_registered = register_key_section([] {
  KeySection s{"shape",
               "shapes",
               "A shape selects points: a body's geometry (sampled on its lattice), a condition's "
               "or a history quantity's region, a no-failure zone. Its `type` picks its keys.",
               {{"type", K::text, "-", kRequired, "the kind of shape"}}};
  s.discriminator = "type";
  return s;
}());

const bool box_registered = register_key_variant(
    "shape",
    {"box",
     "an axis-aligned box (a rectangle in 2D)",
     {{"min", K::vector, "m", kRequired, "the lowest corner"},
      {"max", K::vector, "m", kRequired, "the highest corner", {}, "> min in every component"}}});

const bool sphere_registered = register_key_variant(
    "shape", {"sphere",
              "a ball (a disc in 2D)",
              {{"center", K::vector, "m", kRequired, "the centre"},
               {"radius", K::number, "m", kRequired, "the radius", {}, "> 0"}}});

const bool cylinder_registered = register_key_variant(
    "shape", {"cylinder",
              "a circular cylinder (3D), centred on `center`",
              {{"center", K::vector3, "m", kRequired, "the centre of its axis"},
               {"axis", K::vector3, "-", "[0, 0, 1]", "the axis' direction", {}, "non-zero"},
               {"radius", K::number, "m", kRequired, "the radius", {}, "> 0"},
               {"height", K::number, "m", kRequired, "the length along the axis", {}, "> 0"}}});

const bool half_space_registered = register_key_variant(
    "shape", {"half_space",
              "the points on the side of a plane (a line in 2D) that the normal points to",
              {{"point", K::vector, "m", kRequired, "a point of the plane"},
               {"normal", K::vector, "-", kRequired, "the plane's normal", {}, "non-zero"}}});

const bool mesh_registered = register_key_variant("shape", [] {
  KeyVariant v{"mesh", "the inside of a triangle surface (3D)", mesh_file_keys()};
  v.keys.push_back({"inside_test",
                    K::text,
                    "-",
                    "strict",
                    "strict: a closed surface; tolerant: a surface with small gaps",
                    {"strict", "tolerant"}});
  return v;
}());

const bool mesh_wall_registered = register_key_section(
    {"mesh_wall", "mesh_wall",
     "A rigid body's triangle surface: contact acts on the triangles themselves.",
     mesh_file_keys()});

const bool rotation_registered = register_key_section(
    {"rotation",
     "rotation",
     "A rotation of a mesh by an angle about an axis through the origin.",
     {{"axis", K::vector3, "-", kRequired, "the axis' direction", {}, "non-zero"},
      {"degrees", K::number, "degree", kRequired, "the angle (right-handed about the axis)"}}});

}  // namespace

}  // namespace ckpd
