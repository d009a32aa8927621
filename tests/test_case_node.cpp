// CaseNode (src/input/case_node.hpp), the YAML wrapper every reader uses: typed reads that name
// the file, line and key path of a bad value, and unknown keys refused by finish().
#include <yaml-cpp/yaml.h>

#include <catch2/catch.hpp>
#include <functional>
#include <string>

#include "src/input/case_node.hpp"

using ckpd::CaseError;
using ckpd::CaseNode;

namespace {
CaseNode parse(const std::string& text) {
  return CaseNode(YAML::Load(text), "case.yaml");
}
std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const CaseError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST_CASE("typed reads return the values and name file, line and key path when wrong",
          "[case_node]") {
  const CaseNode root = parse("a:\n  x: 2.5\n  n: 3\n  flag: yes\n  v: [1, 2, 3]\n  bad: -1\n");
  const CaseNode a = root.required("a");
  CHECK(a.required("x").as_double() == 2.5);
  CHECK(a.required("n").as_integer() == 3);
  CHECK(a.required("flag").as_bool());
  CHECK(a.required("v").as_vector(3) == ckpd::Vec3(1, 2, 3));
  const std::string e = error_of([&] { a.required("bad").as_positive(); });
  CHECK(e.find("case.yaml:6") != std::string::npos);
  CHECK(e.find("a.bad") != std::string::npos);
  CHECK(e.find("positive") != std::string::npos);
}

TEST_CASE("a missing required key and a wrong vector length are errors naming the key",
          "[case_node]") {
  const CaseNode root = parse("a: {v: [1, 2]}\n");
  CHECK(error_of([&] { root.required("velocity"); }).find("missing required key 'velocity'") !=
        std::string::npos);
  CHECK(error_of([&] { root.required("a").required("v").as_vector(3); }).find("a.v") !=
        std::string::npos);
  CHECK_FALSE(root.optional("velocity").has_value());
  CHECK(root.has("a"));
}

TEST_CASE("finish refuses a key nobody read and accepts a fully read map", "[case_node]") {
  const CaseNode ok = parse("x: 1\n");
  ok.required("x").as_double();
  CHECK_NOTHROW(ok.finish());
  const CaseNode extra = parse("x: 1\ny: 2\n");
  extra.required("x").as_double();
  const std::string e = error_of([&] { extra.finish(); });
  CHECK(e.find("unknown key 'y'") != std::string::npos);
  CHECK(e.find("case.yaml:2") != std::string::npos);
}

TEST_CASE("a non-finite or out-of-range number is refused", "[case_node]") {
  const CaseNode root = parse("a: .inf\nb: 5\n");
  CHECK_FALSE(error_of([&] { root.required("a").as_positive(); }).empty());
  CHECK_FALSE(error_of([&] { root.required("b").as_in_range(0, 1, "a fraction"); }).empty());
  CHECK(root.required("b").as_in_range(0, 10, "a count") == 5);
}
