#pragma once
// The case file's keys as one table: for every section (a kind of map the case file holds: the
// top level, a body, a material, `time`, ...) each key with its value type, SI unit, default,
// allowed values and one-line meaning. It drives the loader and the reference: a CaseNode bound
// to a section reads only keys the section declares (reading another is a programming error),
// its unknown-key errors suggest the section's keys, `ckpd schema` prints the table as a JSON
// Schema and docs/CASE_FILE.md is generated from it (src/input/key_reference.hpp).
//
// Registered types add their own keys as variants of a section, picked by a discriminator key
// (a shape's `type`, a material's `model`, a contact law's `law`), like the types themselves.
#include <map>
#include <string>
#include <vector>

namespace ckpd {

// What a key's value is: its JSON Schema and the reference's "type" column follow from it.
enum class ValueKind {
  number,             // a number
  integer,            // a whole number
  boolean,            // true or false
  text,               // a string (`allowed` lists its values when they are fixed)
  names,              // a list of strings
  vector,             // [x, y] in 2D, [x, y, z] in 3D
  vector3,            // [x, y, z] (a key of 3D bodies only)
  number_or_vector,   // a number in 2D (about z), [x, y, z] in 3D
  number_or_pair,     // a number, or [a, b]: one value per side of a contact pair
  numbers,            // a list of numbers
  vectors,            // a list of [x, y(, z)] points
  polygons,           // a list of lists of points
  rows,               // a list of rows of numbers
  number_or_auto,     // a number or the word `auto`
  section,            // a map of the keys of section `ref`
  sections,           // a list of such maps
  named_sections,     // a map from names to such maps
  vector_or_section,  // [x, y(, z)], or a map of section `ref`
  number_or_section,  // a number, or a map of section `ref`
};

// The default column's word for a key that must be given.
inline constexpr const char* kRequired = "required";

struct KeySpec {
  std::string name{};
  ValueKind kind = ValueKind::number;
  std::string unit{};      // SI unit of the value; "-" for none (a count, a ratio, a name)
  std::string fallback{};  // what holds when the key is left out; kRequired when it must be given
  std::string meaning{};   // one line
  std::vector<std::string> allowed{};  // the values of a text key (or of a list's strings)
  std::string range{};  // the numbers allowed ("> 0", "(-1, 0.5)"), for the reference
  std::string ref{};    // the section of a map value
  bool required() const { return fallback == kRequired; }
};

// The keys one value of the discriminator adds (`type: box` adds min and max).
struct KeyVariant {
  std::string value{};
  std::string meaning{};
  std::vector<KeySpec> keys{};
};

struct KeySection {
  std::string name{};             // the schema's $defs name and the reference's anchor
  std::string title{};            // the reference's heading
  std::string meaning{};          // a paragraph for the reference
  std::vector<KeySpec> keys{};    // every map of the section takes these
  std::string discriminator{};    // the key whose value picks a variant, or ""
  std::string default_variant{};  // the variant when the discriminator is left out ("": none)
  // Without the discriminator any variant's keys may be given (a contact pair inherits its law
  // from `contact`), and the variants' keys are never required in this section.
  bool variants_inherited = false;
  std::vector<KeyVariant> variants{};  // sorted by value (the default first) once registered
  // A map holding `alternative_key` is a map of section `alternative` (a body with `rigid` is a
  // rigid body).
  std::string alternative_key{}, alternative{};
  // Keys of this other section that the loader reads here only to refuse them with a message
  // of their own (`horizon` on a rigid body); they are not keys of this section.
  std::string refuses_keys_of{};
  std::vector<std::vector<std::string>> exactly_one{};  // key groups of which a map gives one

  // The key `key` of the common keys or of variant `variant` (any variant when null).
  const KeySpec* find(const std::string& key, const std::string* variant = nullptr) const;
  const KeyVariant* find_variant(const std::string& value) const;
  // The keys a map of the section with discriminator value `variant` (null: unknown) takes.
  std::vector<std::string> key_names(const std::string* variant) const;
};

// Registers a section (its variants merge with those registered for it before or after).
bool register_key_section(KeySection section);
bool register_key_variant(const std::string& section, KeyVariant variant);
// Null when no section of that name is registered.
const KeySection* find_key_section(const std::string& name);
// Every registered section, by name.
const std::map<std::string, KeySection>& key_sections();

// The section whose top-level map is a case file.
inline constexpr const char* kCaseSection = "case";

}  // namespace ckpd
