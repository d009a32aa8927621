// Sweep files: value generators, derived expressions, combinations, and bad input refused with
// file, line and key before any run starts.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>

#include "src/sweep/expression.hpp"
#include "src/sweep/generators.hpp"
#include "src/sweep/json_path.hpp"
#include "src/sweep/sweep_file.hpp"
#include "src/sweep/sweep_table.hpp"
#include "sweep_fixtures.hpp"

using namespace ckpd::sweep;
using ckpd::testing::fresh_dir;
using ckpd::testing::write_file;

namespace {

// Writes a sweep over the tiny base case with `body` after the `base:` line and loads it.
Sweep load(const std::filesystem::path& dir, const std::string& body) {
  ckpd::testing::write_sweep_base(dir);
  return load_sweep(write_file(dir / "sweep.yaml", "base: base.yaml\n" + body));
}

std::string load_error(const std::string& body) {
  const auto dir = fresh_dir("sweep-file");
  try {
    load(dir, body);
  } catch (const SweepError& e) {
    return e.what();
  } catch (const ckpd::CaseError& e) {
    return std::string("CaseError: ") + e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("expressions follow arithmetic precedence and read parameters", "[sweep]") {
  const std::map<std::string, double> v{{"spacing", 0.002}, {"a", 3}};
  CHECK(Expression("3.015 * spacing").evaluate(v) == Approx(0.00603));
  CHECK(Expression("1 + 2 * 3 ^ 2").evaluate(v) == 19);
  CHECK(Expression("2 ^ 3 ^ 2").evaluate(v) == 512);  // right-associative
  CHECK(Expression("-a ^ 2").evaluate(v) == -9);
  CHECK(Expression("(1 + a) / 2 - -1").evaluate(v) == 3);
  CHECK(Expression("sqrt(a * 12) + max(1, a) + 2 * pi").evaluate(v) == Approx(9 + 2 * M_PI));
  CHECK(Expression("a * spacing").names() == std::set<std::string>{"a", "spacing"});
  CHECK_THROWS_WITH(Expression("2 * (a + 1"), Catch::Contains("expected ')'"));
  CHECK_THROWS_WITH(Expression("2 * * a"), Catch::Contains("at character 5"));
  CHECK_THROWS_WITH(Expression("foo(1)"), Catch::Contains("known function"));
  CHECK_THROWS_WITH(Expression("1 / (a - 3)").evaluate(v), Catch::Contains("not a finite"));
  CHECK_THROWS_WITH(Expression("b + 1").evaluate(v), Catch::Contains("'b'"));
}

TEST_CASE("ranges hit both ends and log ranges are geometric", "[sweep]") {
  CHECK(linear_range(10, 50, 5) == std::vector<double>{10, 20, 30, 40, 50});
  const auto g = log_range(1e-3, 1e1, 5);
  REQUIRE(g.size() == 5);
  CHECK(g.front() == 1e-3);
  CHECK(g.back() == 1e1);
  for (std::size_t i = 1; i < g.size(); ++i) CHECK(g[i] / g[i - 1] == Approx(10));
  CHECK(format_number(0.1 + 0.2) == "0.30000000000000004");
  CHECK(format_number(0.001) == "0.001");
}

TEST_CASE("a Latin hypercube puts one sample in every stratum of every parameter", "[sweep]") {
  const std::vector<SampleRange> dims{{0, 1, false}, {1, 100, true}};
  const int n = 10;
  const auto s = latin_hypercube(dims, n, 7);
  for (std::size_t d = 0; d < dims.size(); ++d) {
    std::set<int> strata;
    for (const auto& row : s) {
      const double u = dims[d].log ? std::log(row[d]) / std::log(100.0) : row[d];
      strata.insert(static_cast<int>(u * n));
    }
    CHECK(strata.size() == static_cast<std::size_t>(n));
  }
  CHECK(latin_hypercube(dims, n, 7) == s);  // the seed decides
  CHECK(latin_hypercube(dims, n, 8) != s);
  CHECK(random_samples(dims, n, 7) == random_samples(dims, n, 7));
}

TEST_CASE("metric paths pick list elements by name or index", "[sweep]") {
  const auto j = nlohmann::json::parse(
      R"({"energy": {"dissipated": 1.5}, "bodies": [{"name": "disc", "fragments": 3}],
          "contact": {"body_motion": [{"name": "sphere", "velocity": [0, 0, -42.5]}]}})");
  std::string missing;
  CHECK(json_cell(*find_json(j, "energy.dissipated", missing)) == "1.5");
  CHECK(json_cell(*find_json(j, "bodies.disc.fragments", missing)) == "3");
  CHECK(json_cell(*find_json(j, "bodies[0].fragments", missing)) == "3");
  CHECK(json_cell(*find_json(j, "contact.body_motion.sphere.velocity[2]", missing)) == "-42.5");
  CHECK_FALSE(find_json(j, "bodies.plate.fragments", missing));
  CHECK(missing == "bodies.plate");
  CHECK_THROWS(split_json_path("energy..dissipated"));
  CHECK_THROWS(split_json_path("velocity[x]"));
}

TEST_CASE("grid, zip, table and derived values resolve to the expected runs", "[sweep]") {
  const auto dir = fresh_dir("sweep-combine");
  SECTION("grid: the first parameter varies slowest; derived values follow") {
    const Sweep s = load(dir, R"(parameters:
  dx: {key: bodies.block.spacing, values: [0.001, 0.002]}
  m: {key: bodies.block.horizon_ratio, range: {from: 2, to: 4, count: 3}}
  vx: {key: conditions.0.value.0, expr: "10 * m * dx"}
)");
    REQUIRE(s.runs.size() == 6);
    CHECK(s.runs[4].values[0].text == "0.002");
    CHECK(s.runs[4].values[1].text == "3");
    CHECK(*s.runs[4].values[2].number == Approx(0.06));
    CHECK(s.runs[4].overrides.back() == "conditions.0.value.0=" + s.runs[4].values[2].text);
    std::set<std::string> hashes;
    for (const Run& r : s.runs) hashes.insert(r.hash);
    CHECK(hashes.size() == 6);
    CHECK(s.runs[5].folder == "0005-" + s.runs[5].hash.substr(0, 8));
  }
  SECTION("zip: values move together") {
    const Sweep s = load(dir, R"(combine: zip
parameters:
  dx: {key: bodies.block.spacing, values: [0.001, 0.002]}
  m: {key: bodies.block.horizon_ratio, values: [3, 4]}
)");
    REQUIRE(s.runs.size() == 2);
    CHECK(s.runs[1].description == "dx=0.002 m=4");
  }
  SECTION("an inline table gives one run per row with its description") {
    const Sweep s = load(dir, R"(parameters:
  dx: {key: bodies.block.spacing}
  m: {key: bodies.block.horizon_ratio, values: [3, 4]}
table:
  - {description: fine, dx: 0.001}
  - {description: coarse, dx: 0.002}
)");
    REQUIRE(s.runs.size() == 4);
    CHECK(s.runs[2].description == "coarse m=3");
  }
  SECTION("a TSV table file, yade-batch style") {
    write_file(dir / "runs.tsv",
               "# comment\ndescription\tdx\tm\nfine\t0.001\t3\ncoarse\t0.002\t4\n");
    const Sweep s = load(dir, R"(parameters:
  dx: {key: bodies.block.spacing}
  m: {key: bodies.block.horizon_ratio}
  h: {expr: "m * dx"}
table: runs.tsv
)");
    REQUIRE(s.runs.size() == 2);
    CHECK(s.runs[1].description == "coarse");
    CHECK(*s.runs[1].values[2].number == Approx(0.008));
  }
  SECTION("Latin hypercube samples with a seed") {
    const Sweep s = load(dir, R"(combine: latin_hypercube
samples: 5
seed: 3
parameters:
  m: {key: bodies.block.horizon_ratio, range: {from: 2.5, to: 4}}
)");
    REQUIRE(s.runs.size() == 5);
    for (const Run& r : s.runs) CHECK((*r.values[0].number >= 2.5 && *r.values[0].number <= 4));
  }
}

TEST_CASE("bad sweep input names the file, line and key", "[sweep]") {
  CHECK_THAT(load_error("parameters:\n  dx: {key: bodies.block.spacng, values: [1]}\n"),
             Catch::Contains("sweep.yaml:3: parameters.dx.key: 'bodies.block.spacng' does not "
                             "exist in the base case"));
  CHECK_THAT(load_error("parameters:\n  dx: {key: bodies.plate.spacing, values: [1]}\n"),
             Catch::Contains("(no 'bodies.plate')"));
  CHECK_THAT(load_error("parameters:\n  dx: {key: bodies.block.spacing, values: []}\n"),
             Catch::Contains("sweep.yaml:3: parameters.dx.values: an empty list of values"));
  CHECK_THAT(load_error("parameters:\n  dx:\n    key: bodies.block.spacing\n"
                        "    range: {from: 1, to: 2}\n"),
             Catch::Contains("sweep.yaml:5: parameters.dx.range: missing required key 'count'"));
  CHECK_THAT(load_error("parameters:\n  dx:\n    key: bodies.block.spacing\n"
                        "    range: [1, 2, 3]\n"),
             Catch::Contains("sweep.yaml:5: parameters.dx.range: a malformed range"));
  CHECK_THAT(load_error("parameters:\n  dx: {key: bodies.block.spacing, range: {from: 0, to: "
                        "1, count: 3, scale: log}}\n"),
             Catch::Contains("a log range needs from > 0"));
  CHECK_THAT(load_error("parameters:\n  dx: {key: bodies.block.spacing, range: {from: 1, to: "
                        "2, count: 0}}\n"),
             Catch::Contains("a count from 1"));
  CHECK_THAT(load_error("parameters:\n  h: {key: bodies.block.spacing, expr: \"2 * dy\"}\n"
                        "  m: {values: [1]}\n"),
             Catch::Contains("'dy' is not a parameter"));
  CHECK_THAT(load_error("parameters:\n  a: {expr: \"b\"}\n  b: {expr: \"a\"}\n"),
             Catch::Contains("cycle"));
  CHECK_THAT(load_error("parameters:\n  a: {values: [1, 2], zip: g}\n  b: {values: [1], zip: g}\n"),
             Catch::Contains("which has 2 values; this has 1"));
  CHECK_THAT(load_error("parameters:\n  a: {values: [1], colour: red}\n"),
             Catch::Contains("unknown key 'colour'"));
  CHECK_THAT(load_error("set: {time.end: 1e-3, materials.iron.density: 1}\nparameters:\n  a: "
                        "{values: [1]}\n"),
             Catch::Contains("sweep.yaml:2: set.materials.iron.density"));
  CHECK_THAT(load_error("parameters:\n  a: {values: [1]}\nmetrics: {e: \"energy..x\"}\n"),
             Catch::Contains("an empty key"));
  CHECK_THROWS_WITH(parse_shard("3/2"), Catch::Contains("1 <= I <= N"));
  CHECK_THROWS_WITH(parse_shard("0/2"), Catch::Contains("1 <= I <= N"));
  CHECK_THROWS_WITH(parse_shard("1-2"), Catch::Contains("expected I/N"));
  CHECK(parse_shard("2/3").contains(4));
  CHECK_FALSE(parse_shard("2/3").contains(3));
}
