// The keys of conditions in the key table (src/input/key_table.hpp): one variant per condition
// type of src/engine/conditions/, and the tables over time their values may be.
#include "src/input/key_table.hpp"

namespace ckpd {

namespace {

using K = ValueKind;

const char* const kVelocityUnit = "m/s";

KeySpec components_key() {
  return {"components",
          K::names,
          "-",
          "all (x, y and, in 3D, z)",
          "the velocity components prescribed; the others move freely",
          {"x", "y", "z"}};
}
KeySpec direction_key() {
  return {"direction", K::vector, "-", kRequired, "the load's direction (normalised)",
          {},          "non-zero"};
}

const bool condition_registered = register_key_section([] {
  KeySection s{"condition",
               "conditions entries",
               "An initial or boundary condition, or a load, on a body's points. Its `type` picks "
               "its keys.",
               {{"body", K::text, "-", kRequired, "the name of a body in `bodies`"},
                {"type", K::text, "-", kRequired, "the kind of condition"},
                {"region",
                 K::section,
                 "-",
                 "the whole body",
                 "the shape that selects the points",
                 {},
                 "",
                 "shape"}}};
  s.discriminator = "type";
  return s;
}());

const bool velocity_registered = register_key_variant(
    "condition", {"velocity",
                  "a prescribed velocity, constant (optionally ramped from 0) or a table over time",
                  {{"value",
                    K::vector_or_section,
                    kVelocityUnit,
                    kRequired,
                    "the velocity, or a table of it over time",
                    {},
                    "",
                    "time_table"},
                   components_key(),
                   {"ramp_time",
                    K::number,
                    "s",
                    "0 (no ramp)",
                    "the velocity rises linearly from 0 over this time (constant value only)",
                    {},
                    ">= 0"},
                   {"duration",
                    K::number,
                    "s",
                    "none (for the whole run)",
                    "prescribed for 0 <= t <= duration only; then the points move freely",
                    {},
                    "> ramp_time"}}});

const bool velocity_table_registered = register_key_variant(
    "condition",
    {"velocity_table",
     "a prescribed velocity tabulated over time (the same as velocity with a table value)",
     {{"times", K::numbers, "s", kRequired, "the times, increasing", {}, ">= 0"},
      {"values", K::vectors, kVelocityUnit, kRequired, "the velocity at each time"},
      {"interpolation", K::text, "-", "linear", "between the times", {"linear", "step"}},
      components_key()}});

const bool fixed_registered = register_key_variant(
    "condition", {"fixed", "zero velocity (on all or some components)", {components_key()}});

const bool initial_velocity_registered = register_key_variant(
    "condition",
    {"initial_velocity",
     "the velocity at t = 0, value + angular_velocity x (X - center); then free",
     {{"value", K::vector, kVelocityUnit, "0", "the translation velocity"},
      {"angular_velocity", K::number_or_vector, "rad/s", "0",
       "the angular velocity (a number, about z, in 2D)"},
      {"center", K::vector, "m", "required with angular_velocity", "the centre of the rotation"}}});

const bool pressure_pulse_registered = register_key_variant(
    "condition",
    {"pressure_pulse",
     "the body-force pulse p(t)/dx on a layer of points, p(t) = p0 (1 - (2t/t1 - 1)^2) for "
     "t <= t1, then 0",
     {{"peak", K::number, "Pa (N/m in 2D)", kRequired, "the peak p0"},
      {"duration", K::number, "s", kRequired, "the duration t1", {}, "> 0"},
      direction_key()}});

const bool gravity_registered =
    register_key_variant("condition", {"gravity",
                                       "a uniform acceleration g: body force density rho g",
                                       {{"acceleration",
                                         K::vector_or_section,
                                         "m/s^2",
                                         kRequired,
                                         "g, or a table of it over time",
                                         {},
                                         "",
                                         "time_table"}}});

const bool pressure_registered = register_key_variant(
    "condition",
    {"pressure",
     "a pressure p(t) as the body force p(t)/dx on a layer of points one spacing thick",
     {{"value",
       K::number_or_section,
       "Pa (N/m in 2D)",
       kRequired,
       "the pressure, or a table of it over time",
       {},
       "",
       "time_table"},
      direction_key()}});

const bool time_table_registered = register_key_section(
    {"time_table",
     "tables over time",
     "A value given over time: rows [t, value...] with increasing times; before the first row "
     "the first value holds, after the last the last.",
     {{"table", K::rows, "s, then the value's unit", kRequired,
       "the rows: [t, v], [t, vx, vy] or [t, vx, vy, vz]"},
      {"interpolation", K::text, "-", "linear", "between the rows", {"linear", "step"}}}});

}  // namespace

}  // namespace ckpd
