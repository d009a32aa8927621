// The case file's top level, `time` and `output` in the key table (src/input/key_table.hpp).
#include "src/case/keys/case_keys.hpp"

#include <stdexcept>

#include "src/input/key_table.hpp"
#include "src/input/nearest_name.hpp"
#include "src/output/field_table.hpp"
#include "src/output/history_quantities.hpp"

namespace ckpd {

namespace {

using K = ValueKind;

const bool case_registered = register_key_section(
    {kCaseSection,
     "Top level",
     "A case file is a YAML map of these sections. Units are SI throughout (m, s, kg, Pa, J).",
     {{"description", K::text, "-", "none", "one line shown in the run's log and summary"},
      {"materials",
       K::named_sections,
       "-",
       "none (rigid bodies and DEM spheres may give their mass, E and nu themselves)",
       "the materials, by name: `name: {model: ..., density: ..., ...}`",
       {},
       "",
       "material"},
      {"max_memory",
       K::number,
       "B",
       "the available memory (MemAvailable)",
       "the most memory the bodies may take; a case over it is refused before it is built",
       {},
       "1e6 to 1e18"},
      {"bodies", K::sections, "-", kRequired, "the bodies, deformable or rigid", {}, "", "body"},
      {"conditions",
       K::sections,
       "-",
       "none",
       "initial and boundary conditions and loads",
       {},
       "",
       "condition"},
      {"contact",
       K::section,
       "-",
       "no contact",
       "contact between bodies (and within one)",
       {},
       "",
       "contact"},
      {"time", K::section, "-", kRequired, "the run's length and time step", {}, "", "time"},
      {"output",
       K::section,
       "-",
       "history rows only (about 200 per run)",
       "history rows, field frames and checkpoints",
       {},
       "",
       "output"}}});

KeySection time_section() {
  KeySection s{
      "time",
      "time",
      "The run's length (`end` or `steps`, one of them) and its time step.",
      {{"end", K::number, "s", "give end or steps", "the end time", {}, "> 0"},
       {"steps", K::integer, "-", "give end or steps", "the number of steps", {}, ">= 0"},
       {"dt",
        K::number_or_auto,
        "s",
        "auto",
        "the time step; auto: safety x the stable-step estimate",
        {},
        "> 0, or auto"},
       {"safety",
        K::number,
        "-",
        "0.8",
        "the fraction of the stable-step estimate taken as dt",
        {},
        "(0, 1]"},
       {"allow_unstable_dt", K::boolean, "-", "false",
        "accept a dt above the stable-step estimate"},
       {"step_mode",
        K::text,
        "-",
        "fixed",
        "fixed: dt for the whole run; adaptive: each step follows the current stable step, never "
        "above dt",
        {"fixed", "adaptive"}},
       {"smallest_step",
        K::number,
        "s",
        "1e-12 x dt",
        "with step_mode adaptive, the run stops when the step would fall below this",
        {},
        "> 0"}}};
  s.exactly_one = {{"end", "steps"}};
  return s;
}
const bool time_registered = register_key_section(time_section());

const bool output_registered = register_key_section(
    {"output",
     "output",
     "What a run writes besides its summary: history rows (history.csv), field frames (HDF5 and "
     "XDMF) and checkpoints.",
     {{"history_interval",
       K::integer,
       "-",
       "about 200 rows per run",
       "steps between history rows",
       {},
       "> 0"},
      {"checkpoint_interval",
       K::integer,
       "-",
       "none (only on SIGINT or SIGTERM)",
       "steps between checkpoints",
       {},
       "> 0"},
      {"history",
       K::sections,
       "-",
       "none",
       "extra history quantities, one map each",
       {},
       "",
       "history_quantity"},
      {"field_interval",
       K::integer,
       "-",
       "none (no frames)",
       "steps between field frames (or give field_time_interval)",
       {},
       "> 0"},
      {"field_time_interval",
       K::number,
       "s",
       "none (no frames)",
       "time between field frames (or give field_interval)",
       {},
       "> 0"},
      {"fields", K::names, "-", "position, displacement, velocity, damage, body_id",
       "the fields each frame holds (with field_interval or field_time_interval)",
       known_field_names()}}});

const bool history_registered = register_key_section(
    {"history_quantity",
     "output.history entries",
     "One history quantity: its columns are added to history.csv.",
     {{"quantity", K::text, "-", kRequired, "the quantity", row_names(history_quantity_table())},
      {"body", K::text, "-", "required for a one-body quantity", "the body's name"},
      {"bodies", K::names, "-", "required for a two-body quantity",
       "the two bodies' names, [first, second]"},
      {"region",
       K::section,
       "-",
       "required for reaction_force",
       "the shape that selects the body's points",
       {},
       "",
       "shape"},
      {"name", K::text, "-", "the quantity and its bodies' names", "the columns' prefix"}}});

}  // namespace

}  // namespace ckpd

namespace ckpd {

const KeySection& case_key_section() {
  static const KeySection& root = []() -> const KeySection& {
    for (const auto& [name, section] : key_sections()) {
      if (section.title.empty())
        throw std::logic_error("key section '" + name + "' has variants but no keys of its own");
      // A named copy: clang before 16 cannot capture a structured binding.
      const std::string& section_name = name;
      auto check = [&](const KeySpec& k) {
        if (!k.ref.empty() && !find_key_section(k.ref))
          throw std::logic_error("key '" + section_name + "." + k.name + "' names key section '" +
                                 k.ref + "', which is not registered");
      };
      for (const KeySpec& k : section.keys) check(k);
      for (const KeyVariant& v : section.variants)
        for (const KeySpec& k : v.keys) check(k);
    }
    const KeySection* s = find_key_section(kCaseSection);
    if (!s) throw std::logic_error("no key section for the case file");
    return *s;
  }();
  return root;
}

}  // namespace ckpd
