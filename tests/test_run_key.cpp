// The run key (src/sweep/run_key.hpp): what decides a run's results, and only that. A resumed
// sweep trusts it to skip finished runs, so it must change with the physics and not with layout.
#include <yaml-cpp/yaml.h>

#include <catch2/catch.hpp>

#include "src/sweep/run_key.hpp"

using namespace ckpd::sweep;

TEST_CASE("fnv1a matches the published 64-bit FNV-1a values", "[run_key]") {
  // Reference values of the FNV-1a 64 specification (offset basis 14695981039346656037).
  CHECK(fnv1a("") == 0xcbf29ce484222325ull);
  CHECK(fnv1a("a") == 0xaf63dc4c8601ec8cull);
  CHECK(fnv1a("foobar") == 0x85944171f73967e8ull);
  CHECK(hex16(0xcbf29ce484222325ull) == "cbf29ce484222325");
  CHECK(hex16(1) == "0000000000000001");
}

TEST_CASE("the run key ignores layout, comments and the description", "[run_key]") {
  const YAML::Node a = YAML::Load("description: first\nbodies: [{name: b, spacing: 0.001}]\n");
  // Flow and block style are emitted differently, so both are in flow style here.
  const YAML::Node b =
      YAML::Load("# a comment\ndescription: second\nbodies:   [ {name: b,   spacing: 0.001} ]\n");
  CHECK(run_key(a) == run_key(b));
  CHECK(run_key(a).size() == 16);
}

TEST_CASE("the run key changes with any physics value", "[run_key]") {
  const YAML::Node a = YAML::Load("bodies: [{name: b, spacing: 0.001}]\n");
  const YAML::Node b = YAML::Load("bodies: [{name: b, spacing: 0.002}]\n");
  const YAML::Node c = YAML::Load("bodies: [{name: c, spacing: 0.001}]\n");
  CHECK(run_key(a) != run_key(b));
  CHECK(run_key(a) != run_key(c));
}
