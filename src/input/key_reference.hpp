#pragma once
// The key table (src/input/key_table.hpp) as a JSON Schema and as a reference page.
#include <string>
#include <vector>

#include "src/input/key_table.hpp"

namespace ckpd {

// The sections a map of `root` may hold, `root` first, then depth-first in key order (the
// order of the reference page). Throws std::logic_error for a key naming no registered section.
std::vector<const KeySection*> sections_below(const KeySection& root);

// A JSON Schema (draft 2020-12) of a map of `root`: every section is a $defs entry, variants
// are if/then on the discriminator, and unknown keys are refused (unevaluatedProperties).
std::string key_schema_json(const KeySection& root, const std::string& title);

// The reference's "type" column for a key (with a link to its section).
std::string key_type_text(const KeySpec& key);

// The reference page in Markdown: `intro` (Markdown), then one table per section (Key, Type,
// Unit, Default, Allowed, Meaning) and one per variant.
std::string key_reference_markdown(const KeySection& root, const std::string& title,
                                   const std::string& intro);

}  // namespace ckpd
