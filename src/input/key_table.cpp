#include "src/input/key_table.hpp"

#include <algorithm>
#include <stdexcept>

namespace ckpd {

namespace {

std::map<std::string, KeySection>& registry() {
  static std::map<std::string, KeySection> sections;
  return sections;
}

// The default variant first, the others by value: the same order whatever the registration order.
void sort_variants(KeySection& s) {
  std::sort(s.variants.begin(), s.variants.end(), [&](const KeyVariant& a, const KeyVariant& b) {
    const bool ad = a.value == s.default_variant, bd = b.value == s.default_variant;
    return ad != bd ? ad : a.value < b.value;
  });
}

}  // namespace

const KeySpec* KeySection::find(const std::string& key, const std::string* variant) const {
  for (const KeySpec& k : keys)
    if (k.name == key) return &k;
  for (const KeyVariant& v : variants)
    if (!variant || v.value == *variant)
      for (const KeySpec& k : v.keys)
        if (k.name == key) return &k;
  return nullptr;
}

const KeyVariant* KeySection::find_variant(const std::string& value) const {
  for (const KeyVariant& v : variants)
    if (v.value == value) return &v;
  return nullptr;
}

std::vector<std::string> KeySection::key_names(const std::string* variant) const {
  std::vector<std::string> names;
  for (const KeySpec& k : keys) names.push_back(k.name);
  for (const KeyVariant& v : variants)
    if (!variant || v.value == *variant)
      for (const KeySpec& k : v.keys)
        if (std::find(names.begin(), names.end(), k.name) == names.end()) names.push_back(k.name);
  return names;
}

bool register_key_section(KeySection section) {
  KeySection& s = registry()[section.name];
  if (!s.title.empty())
    throw std::logic_error("key section '" + section.name + "' registered twice");
  std::vector<KeyVariant> earlier = std::move(s.variants);
  s = std::move(section);
  for (KeyVariant& v : earlier) s.variants.push_back(std::move(v));
  sort_variants(s);
  return true;
}

bool register_key_variant(const std::string& section, KeyVariant variant) {
  KeySection& s = registry()[section];
  s.name = section;
  if (s.find_variant(variant.value))
    throw std::logic_error("variant '" + variant.value + "' of key section '" + section +
                           "' registered twice");
  s.variants.push_back(std::move(variant));
  sort_variants(s);
  return true;
}

const KeySection* find_key_section(const std::string& name) {
  const auto it = registry().find(name);
  return it == registry().end() ? nullptr : &it->second;
}

const std::map<std::string, KeySection>& key_sections() {
  return registry();
}

}  // namespace ckpd
