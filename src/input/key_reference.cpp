#include "src/input/key_reference.hpp"

#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <stdexcept>

namespace ckpd {

namespace {

using json = nlohmann::ordered_json;

const KeySection& section_named(const std::string& name) {
  const KeySection* s = find_key_section(name);
  if (!s) throw std::logic_error("no key section '" + name + "' is registered");
  return *s;
}

// The keys of a section's variants, the first of each name (for a section whose variants are
// inherited: without the discriminator, any of them).
std::vector<KeySpec> variant_union(const KeySection& s) {
  std::vector<KeySpec> keys;
  std::set<std::string> seen;
  for (const KeyVariant& v : s.variants)
    for (const KeySpec& k : v.keys)
      if (seen.insert(k.name).second) keys.push_back(k);
  return keys;
}

json ref_schema(const std::string& name) {
  const KeySection& s = section_named(name);
  if (s.alternative_key.empty()) return {{"$ref", "#/$defs/" + name}};
  section_named(s.alternative);
  return {{"if", {{"type", "object"}, {"required", {s.alternative_key}}}},
          {"then", {{"$ref", "#/$defs/" + s.alternative}}},
          {"else", {{"$ref", "#/$defs/" + name}}}};
}

json text_schema(const std::vector<std::string>& allowed) {
  json s = {{"type", "string"}};
  if (!allowed.empty()) s["enum"] = allowed;
  return s;
}

json array_of(json items, int min = 0, int max = 0) {
  json s = {{"type", "array"}, {"items", std::move(items)}};
  if (min) s["minItems"] = min;
  if (max) s["maxItems"] = max;
  return s;
}

json value_schema(const KeySpec& k) {
  const json number = {{"type", "number"}};
  const json vector = array_of(number, 2, 3);
  switch (k.kind) {
    case ValueKind::number:
      return number;
    case ValueKind::integer:
      return {{"type", "integer"}};
    case ValueKind::boolean:
      return {{"type", "boolean"}};
    case ValueKind::text:
      return text_schema(k.allowed);
    case ValueKind::names:
      return array_of(text_schema(k.allowed));
    case ValueKind::vector:
      return vector;
    case ValueKind::vector3:
      return array_of(number, 3, 3);
    case ValueKind::number_or_vector:
      return {{"anyOf", {number, array_of(number, 3, 3)}}};
    case ValueKind::number_or_pair:
      return {{"anyOf", {number, array_of(number, 1, 2)}}};
    case ValueKind::numbers:
      return array_of(number);
    case ValueKind::vectors:
      return array_of(vector);
    case ValueKind::polygons:
      return array_of(array_of(vector));
    case ValueKind::rows:
      return array_of(array_of(number, 2, 4));
    case ValueKind::number_or_auto:
      return {{"anyOf", {number, {{"const", "auto"}}}}};
    case ValueKind::section:
      return ref_schema(k.ref);
    case ValueKind::sections:
      return array_of(ref_schema(k.ref));
    case ValueKind::named_sections:
      return {{"type", "object"}, {"additionalProperties", ref_schema(k.ref)}};
    case ValueKind::vector_or_section:
      return {{"anyOf", {vector, ref_schema(k.ref)}}};
    case ValueKind::number_or_section:
      return {{"anyOf", {number, ref_schema(k.ref)}}};
  }
  throw std::logic_error("key '" + k.name + "' has no value kind");
}

std::string description(const KeySpec& k) {
  std::string text = k.meaning;
  if (!k.unit.empty() && k.unit != "-") text += ". Unit: " + k.unit;
  if (!k.range.empty()) text += ". Allowed: " + k.range;
  text += ". Default: " + k.fallback + ".";
  return text;
}

// Properties and required keys of `keys` (no `required` when `optional`).
void add_keys(json& schema, const std::vector<KeySpec>& keys, bool optional = false) {
  json properties = json::object(), required = json::array();
  for (const KeySpec& k : keys) {
    json p = value_schema(k);
    p["description"] = description(k);
    properties[k.name] = std::move(p);
    if (k.required() && !optional) required.push_back(k.name);
  }
  schema["properties"] = std::move(properties);
  if (!required.empty()) schema["required"] = std::move(required);
}

json section_schema(const KeySection& s) {
  json d = {{"type", "object"}, {"title", s.title}, {"description", s.meaning}};
  add_keys(d, s.keys);
  json all = json::array();
  if (!s.discriminator.empty()) {
    json values = json::array();
    for (const KeyVariant& v : s.variants) values.push_back(v.value);
    d["properties"][s.discriminator]["enum"] = values;
    for (const KeyVariant& v : s.variants) {
      json when = {{"properties", {{s.discriminator, {{"const", v.value}}}}}};
      if (v.value != s.default_variant) when["required"] = {s.discriminator};
      json then = {{"description", v.meaning}};
      add_keys(then, v.keys, s.variants_inherited);
      all.push_back({{"if", std::move(when)}, {"then", std::move(then)}});
    }
    if (s.variants_inherited) {
      json then = json::object();
      add_keys(then, variant_union(s), true);
      all.push_back(
          {{"if", {{"not", {{"required", {s.discriminator}}}}}}, {"then", std::move(then)}});
    }
  }
  for (const std::vector<std::string>& group : s.exactly_one) {
    json one = json::array();
    for (const std::string& k : group) one.push_back({{"required", {k}}});
    all.push_back({{"oneOf", std::move(one)}});
  }
  if (!all.empty()) d["allOf"] = std::move(all);
  d["unevaluatedProperties"] = false;
  return d;
}

// "a box" as a sentence: "A box."
std::string sentence(std::string text) {
  if (!text.empty() && text[0] >= 'a' && text[0] <= 'z')
    text[0] = static_cast<char>(text[0] - 'a' + 'A');
  return text + ".";
}

std::string cell(std::string text) {
  std::string out;
  for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

std::string code_list(const std::vector<std::string>& values) {
  std::string out;
  for (const std::string& v : values) out += (out.empty() ? "`" : ", `") + v + "`";
  return out;
}

std::string link(const std::string& section) {
  const KeySection& s = section_named(section);
  std::string text = "[" + s.title + "](#" + section + ")";
  if (!s.alternative.empty())
    text += " or [" + section_named(s.alternative).title + "](#" + s.alternative + ")";
  return text;
}

void table(std::ostringstream& out, const KeySection& s, const std::vector<KeySpec>& keys,
           bool discriminator_row) {
  out << "| Key | Type | Unit | Default | Allowed | Meaning |\n"
      << "|---|---|---|---|---|---|\n";
  for (const KeySpec& k : keys) {
    std::string allowed = k.allowed.empty() ? k.range : code_list(k.allowed);
    if (discriminator_row && k.name == s.discriminator) {
      std::vector<std::string> values;
      for (const KeyVariant& v : s.variants) values.push_back(v.value);
      allowed = code_list(values);
    }
    out << "| `" << k.name << "` | " << cell(key_type_text(k)) << " | " << cell(k.unit) << " | "
        << cell(k.fallback) << " | " << cell(allowed) << " | " << cell(k.meaning) << " |\n";
  }
}

}  // namespace

std::vector<const KeySection*> sections_below(const KeySection& root) {
  std::vector<const KeySection*> order;
  std::set<std::string> seen;
  auto visit = [&](const KeySection& s, auto& self) -> void {
    if (!seen.insert(s.name).second) return;
    order.push_back(&s);
    auto follow = [&](const KeySpec& k) {
      if (k.ref.empty()) return;
      const KeySection& ref = section_named(k.ref);
      self(ref, self);
      if (!ref.alternative.empty()) self(section_named(ref.alternative), self);
    };
    for (const KeySpec& k : s.keys) follow(k);
    for (const KeyVariant& v : s.variants)
      for (const KeySpec& k : v.keys) follow(k);
  };
  visit(root, visit);
  return order;
}

std::string key_type_text(const KeySpec& k) {
  switch (k.kind) {
    case ValueKind::number:
      return "number";
    case ValueKind::integer:
      return "integer";
    case ValueKind::boolean:
      return "true or false";
    case ValueKind::text:
      return "string";
    case ValueKind::names:
      return "list of strings";
    case ValueKind::vector:
      return "[x, y] (2D) or [x, y, z] (3D)";
    case ValueKind::vector3:
      return "[x, y, z]";
    case ValueKind::number_or_vector:
      return "number (2D) or [x, y, z] (3D)";
    case ValueKind::number_or_pair:
      return "number or [first, second]";
    case ValueKind::numbers:
      return "list of numbers";
    case ValueKind::vectors:
      return "list of [x, y(, z)]";
    case ValueKind::polygons:
      return "list of lists of [x, y(, z)]";
    case ValueKind::rows:
      return "list of rows of numbers";
    case ValueKind::number_or_auto:
      return "number or `auto`";
    case ValueKind::section:
      return "map: " + link(k.ref);
    case ValueKind::sections:
      return "list of maps: " + link(k.ref);
    case ValueKind::named_sections:
      return "map of names to maps: " + link(k.ref);
    case ValueKind::vector_or_section:
      return "[x, y(, z)] or map: " + link(k.ref);
    case ValueKind::number_or_section:
      return "number or map: " + link(k.ref);
  }
  throw std::logic_error("key '" + k.name + "' has no value kind");
}

std::string key_schema_json(const KeySection& root, const std::string& title) {
  json defs = json::object();
  for (const KeySection* s : sections_below(root)) defs[s->name] = section_schema(*s);
  const json schema = {{"$schema", "https://json-schema.org/draft/2020-12/schema"},
                       {"title", title},
                       {"$ref", "#/$defs/" + root.name},
                       {"$defs", std::move(defs)}};
  return schema.dump(2) + "\n";
}

std::string key_reference_markdown(const KeySection& root, const std::string& title,
                                   const std::string& intro) {
  const std::vector<const KeySection*> sections = sections_below(root);
  std::ostringstream out;
  out << "# " << title << "\n\n" << intro << "\n## Sections\n\n";
  for (const KeySection* s : sections) out << "- [" << s->title << "](#" << s->name << ")\n";
  for (const KeySection* s : sections) {
    out << "\n<a id=\"" << s->name << "\"></a>\n\n## " << s->title << "\n\n"
        << s->meaning << "\n\n";
    table(out, *s, s->keys, true);
    for (const KeyVariant& v : s->variants) {
      out << "\n### `" << s->discriminator << ": " << v.value << "`\n\n" << sentence(v.meaning);
      out << "\n\n";
      if (v.keys.empty())
        out << "No keys of its own.\n";
      else
        table(out, *s, v.keys, false);
    }
  }
  return out.str();
}

}  // namespace ckpd
