// The key table (src/input/key_table.hpp) drives the loader and the reference: every key has a
// type, unit, default and meaning; docs/CASE_FILE.md and docs/ckpd.schema.json are what
// `ckpd schema` prints; the registered types (shapes, conditions, materials, contact laws) are
// the table's variants; a CaseNode bound to the table reads only declared keys and names
// unknown ones against it.
#include <yaml-cpp/yaml.h>

#include <catch2/catch.hpp>
#include <fstream>
#include <set>
#include <sstream>

#include "contact/dem_law.hpp"
#include "src/case/keys/case_keys.hpp"
#include "src/case/keys/case_reference.hpp"
#include "src/case/material_model.hpp"
#include "src/engine/condition.hpp"
#include "src/geometry/shape.hpp"
#include "src/input/case_node.hpp"
#include "src/input/key_reference.hpp"
#include "src/input/key_table.hpp"

using namespace ckpd;

namespace {

std::string read_text(const std::string& relative) {
  std::ifstream in(std::string(CKPD_SOURCE_DIR) + "/" + relative);
  REQUIRE(in);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

template <class Registry>
std::set<std::string> names_of(const Registry& registry) {
  std::set<std::string> names;
  for (const auto& [name, entry] : registry) names.insert(name);
  return names;
}

std::set<std::string> variants_of(const std::string& section) {
  std::set<std::string> names;
  for (const KeyVariant& v : find_key_section(section)->variants) names.insert(v.value);
  return names;
}

}  // namespace

TEST_CASE("every section of the table is reached from the case file's top level", "[keys]") {
  std::set<std::string> reached;
  for (const KeySection* s : sections_below(case_key_section())) reached.insert(s->name);
  CHECK(reached == names_of(key_sections()));
}

TEST_CASE("every key of the table has a type, a unit, a default and a meaning", "[keys]") {
  auto check = [](const KeySection& s, const KeySpec& k) {
    INFO(s.name << "." << k.name);
    CHECK_FALSE(k.unit.empty());
    CHECK_FALSE(k.fallback.empty());
    CHECK_FALSE(k.meaning.empty());
    CHECK_FALSE(key_type_text(k).empty());
    CHECK(k.ref.empty() ==
          (k.kind != ValueKind::section && k.kind != ValueKind::sections &&
           k.kind != ValueKind::named_sections && k.kind != ValueKind::vector_or_section &&
           k.kind != ValueKind::number_or_section));
  };
  for (const auto& [name, s] : key_sections()) {
    for (const KeySpec& k : s.keys) check(s, k);
    for (const KeyVariant& v : s.variants)
      for (const KeySpec& k : v.keys) check(s, k);
  }
}

TEST_CASE("every key appears in the reference with its type, unit and default", "[keys]") {
  const std::string page = case_file_reference();
  // No table text holds a '|' (the page would escape it).
  auto row = [](const KeySpec& k) {
    return "| `" + k.name + "` | " + key_type_text(k) + " | " + k.unit + " | " + k.fallback + " |";
  };
  std::size_t rows = 0;
  for (const auto& [name, s] : key_sections()) {
    for (const KeySpec& k : s.keys) {
      INFO(name << "." << k.name);
      CHECK(page.find(row(k)) != std::string::npos);
      ++rows;
    }
    for (const KeyVariant& v : s.variants)
      for (const KeySpec& k : v.keys) {
        INFO(name << " (" << v.value << ")." << k.name);
        CHECK(page.find(row(k)) != std::string::npos);
        ++rows;
      }
  }
  CHECK(rows > 100);
}

TEST_CASE("docs/CASE_FILE.md is the reference that ckpd schema --markdown prints", "[keys]") {
  // To update the page: ckpd schema --markdown > docs/CASE_FILE.md
  CHECK(read_text("docs/CASE_FILE.md") == case_file_reference());
}

TEST_CASE("docs/ckpd.schema.json is the schema that ckpd schema prints", "[keys]") {
  // To update it: ckpd schema > docs/ckpd.schema.json
  CHECK(read_text("docs/ckpd.schema.json") == case_file_schema());
}

TEST_CASE("the table's variants are the registered shapes, conditions, models and laws", "[keys]") {
  CHECK(variants_of("shape") == names_of(shape_registry()));
  CHECK(variants_of("condition") == names_of(condition_registry()));
  CHECK(variants_of("material") == names_of(material_registry()));
  CHECK(variants_of("contact") == names_of(law_registry()));
  CHECK(variants_of("contact_pair") == names_of(law_registry()));
}

TEST_CASE("each contact law's keys are its registered parameters, required alike", "[keys]") {
  const KeySection& contact = *find_key_section("contact");
  for (const auto& [law, type] : law_registry()) {
    INFO(law);
    const KeyVariant* v = contact.find_variant(law);
    REQUIRE(v);
    std::set<std::string> table, registered;
    for (const KeySpec& k : v->keys) table.insert(k.name + (k.required() ? "!" : ""));
    for (const LawParameter& p : type.parameters)
      registered.insert(p.key + (p.required ? "!" : ""));
    CHECK(table == registered);
  }
}

TEST_CASE("a map bound to the table reads only the keys its section declares", "[keys]") {
  CaseNode time(YAML::Load("end: 1\n"), "case.yaml", "time");
  time.set_key_section(find_key_section("time"));
  CHECK(time.required("end").as_double() == 1);
  CHECK_THROWS_AS(time.optional("end_time"), std::logic_error);
  CHECK_THROWS_AS(time.has("horizon"), std::logic_error);
}

TEST_CASE("a shape's keys are those of its type; a key of another type is read to refuse it",
          "[keys]") {
  CaseNode shape(YAML::Load("type: box\nmin: [0, 0]\nmax: [1, 1]\n"), "case.yaml", "geometry");
  shape.set_key_section(find_key_section("shape"));
  CHECK_NOTHROW(shape.optional("radius"));  // a sphere's key: declared, read to refuse it
  CHECK_THROWS_AS(shape.optional("radios"), std::logic_error);
}

TEST_CASE("an unknown key is named with the table's nearest key, read or not", "[keys]") {
  CaseNode time(YAML::Load("end: 1\nsaftey: 0.5\n"), "case.yaml", "time");
  time.set_key_section(find_key_section("time"));
  time.required("end");
  // `safety` was never read: the suggestion comes from the table.
  CHECK_THROWS_WITH(time.finish(), Catch::Contains("case.yaml:2: time.saftey: unknown key "
                                                   "'saftey' (did you mean 'safety'?)"));
}

TEST_CASE("a body with `rigid` takes the rigid body's keys", "[keys]") {
  CaseNode bodies(YAML::Load("bodies:\n  - {name: a, rigid: {motion: free}, spacng: 1}\n"),
                  "case.yaml");
  bodies.set_key_section(&case_key_section());
  const CaseNode body = bodies.required("bodies").elements()[0];
  REQUIRE(body.key_section());
  CHECK(body.key_section()->name == "rigid_body");
  body.required("name");
  body.required("rigid");
  CHECK_THROWS_WITH(body.finish(),
                    Catch::Contains("unknown key 'spacng' (did you mean 'spacing'?)"));
}
