// Regression tests for the inputs of issue 18's fuzz campaign that crashed ckpd, hung it, or
// were silently accepted: each is refused before any work with exit 2, a message naming the
// file, line and key, and no summary.json (or stopped with exit 3 for an instability).
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "run_helpers.hpp"
#include "sweep_fixtures.hpp"

using namespace ckpd::testing;

namespace {

const char* kPlate = R"(# a small 2D plate, SI units
materials:
  steel: {density: 7580, youngs_modulus: 210e9, poisson_ratio: 0.3, fracture_energy: 140}
bodies:
  - name: plate
    material: steel
    dimension: 2
    geometry: {type: box, min: [0, 0], max: [0.05, 0.05]}
    spacing: 0.005
    horizon_ratio: 3.015
time: {steps: 5}
)";

// A sphere dropped on a plate (3D, contact): the impact signatures.
const char* kImpact = R"(# sphere on plate, SI units
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.25}
bodies:
  - name: plate
    material: steel
    geometry: {type: box, min: [-0.01, -0.01, -0.002], max: [0.01, 0.01, 0]}
    spacing: 0.001
    horizon_ratio: 3.015
  - name: ball
    material: steel
    geometry: {type: sphere, center: [0, 0, 0.0025], radius: 0.002}
    spacing: 0.001
    horizon_ratio: 3.015
conditions:
  - {type: initial_velocity, body: ball, value: [0, 0, -10]}
contact:
  stiffness: 1.0e12
time: {steps: 3}
)";

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

// Runs `ckpd run` (and `ckpd check`) on the case; both must exit 2 with every fragment.
void expect_refused(const std::string& case_text, std::initializer_list<std::string> fragments) {
  const auto dir = fresh_dir("hardened");
  const std::string file = write_file(dir / "case.yaml", case_text);
  for (const std::string command : {"run ", "check "}) {
    const CommandResult r =
        run_ckpd(command + file +
                 (command == "run " ? " --quiet --out " + (dir / "out").string() : std::string()));
    INFO(command << "\n" << r.output);
    CHECK(r.exit_code == 2);
    for (const std::string& f : fragments) CHECK(r.output.find(f) != std::string::npos);
  }
  CHECK_FALSE(std::filesystem::exists(dir / "out" / "summary.json"));
}

}  // namespace

TEST_CASE("the base cases run, so each refusal below is about its one change", "[hardened]") {
  for (const char* text : {kPlate, kImpact}) {
    const auto dir = fresh_dir("hardened-good");
    const std::string file = write_file(dir / "case.yaml", text);
    const CommandResult r = run_ckpd("run " + file + " --quiet --out " + (dir / "out").string());
    INFO(r.output);
    CHECK(r.exit_code == 0);
  }
}

TEST_CASE("a key given twice is an error naming its second line", "[hardened]") {
  expect_refused(replace(kPlate, "    spacing: 0.005\n", "    spacing: 0.001\n    spacing: -1\n"),
                 {"case.yaml:10:", "bodies[0].spacing", "given twice"});
  expect_refused(replace(kPlate, "time: {steps: 5}", "time: {steps: 5, steps: 6}"),
                 {"case.yaml:11:", "time.steps", "given twice"});
}

TEST_CASE("a complex YAML key is an error naming its line, not a yaml-cpp exit 1", "[hardened]") {
  expect_refused(std::string(kPlate) + "? [a, b]\n: 1\n",
                 {"case.yaml:12:", "a key must be a plain name"});
}

TEST_CASE("a body name that is not UTF-8 is refused before the run", "[hardened]") {
  expect_refused(replace(kPlate, "name: plate",
                         "name: pl\xff\xfe"
                         "ate"),
                 {"case.yaml:5:", "bodies[0].name", "not valid UTF-8"});
}

TEST_CASE("nesting past yaml-cpp's depth limit names the line, not 'bad file'", "[hardened]") {
  expect_refused(
      std::string(kPlate) + "description: " + std::string(600, '[') + std::string(600, ']') + "\n",
      {"case.yaml:12:", "nested deeper than"});
}

TEST_CASE("coordinates of 1e200 are refused (FCL crashed on them)", "[hardened]") {
  expect_refused(replace(kImpact, "center: [0, 0, 0.0025]", "center: [1e200, 0, 0.0025]"),
                 {"case.yaml:12:", "bodies[1].geometry.center[0]", "magnitude at most 1e30"});
  expect_refused(replace(kImpact, "center: [0, 0, 0.0025]", "center: [1e20, 0, 0.0025]"),
                 {"case.yaml:12:", "bodies[1].geometry", "within 1e+06 m of the origin"});
  expect_refused(replace(kPlate, "min: [0, 0], max: [0.05, 0.05]",
                         "min: [-1e200, -1e200], max: [1e200, 1e200]"),
                 {"case.yaml:8:", "bodies[0].geometry.min[0]", "magnitude at most 1e30"});
}

TEST_CASE("a box too large for the lattice count is refused with the count, not wrapped",
          "[hardened]") {
  // 2e12 x 2e12 sites at 1 um (4e24): the count saturates at 2^64 instead of wrapping to a
  // handful of points.
  expect_refused(
      replace(
          replace(kPlate, "min: [0, 0], max: [0.05, 0.05]", "min: [-1e6, -1e6], max: [1e6, 1e6]"),
          "spacing: 0.005", "spacing: 1e-6"),
      {"case.yaml:8:", "bodies[0].geometry", "over 1.8e+19 lattice sites", "max_points"});
}

TEST_CASE("a spacing below a nanometre is refused naming the key", "[hardened]") {
  expect_refused(replace(kPlate, "spacing: 0.005", "spacing: 1e-22"),
                 {"case.yaml:9:", "bodies[0].spacing", "from 1e-09"});
  expect_refused(replace(kPlate, "spacing: 0.005", "spacing: 1e-300"),
                 {"case.yaml:9:", "bodies[0].spacing", "from 1e-09"});
}

TEST_CASE("a huge horizon ratio is refused before set-up (it never finished)", "[hardened]") {
  expect_refused(replace(kImpact, "    horizon_ratio: 3.015\n  - name: ball",
                         "    horizon_ratio: 1e4\n  - name: ball"),
                 {"case.yaml:9:", "bodies[0].horizon_ratio", "at most 100000 lattice offsets"});
  expect_refused(replace(kPlate, "horizon_ratio: 3.015", "horizon_ratio: 1e12"),
                 {"case.yaml:10:", "bodies[0].horizon_ratio", "over 1.8e+19"});
}

TEST_CASE("a body over the memory budget is refused with the estimate", "[hardened]") {
  // max_memory: 100 points at ~28 bonds is ~115 kB, over a budget of 1e6 bytes only when the
  // body is 10 times finer.
  expect_refused("max_memory: 1e6\n" + replace(kPlate, "spacing: 0.005", "spacing: 0.0005"),
                 {"case.yaml:", "body 'plate' needs at least", "10000 points", "over max_memory"});
  expect_refused("max_memory: 12\n" + std::string(kPlate),
                 {"case.yaml:1:", "max_memory", "a memory limit in bytes"});
}

TEST_CASE("a 17.6 M point box under max_points but over the machine's memory is refused",
          "[hardened]") {
  // The issue's signature: 0.26 m at 1 mm ended after 30 s in std::bad_alloc, exit 1. Its
  // bodies need ~69 GB; refused unless this machine has that much available.
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  long long kib = 0;
  std::string unit;
  while (meminfo >> key >> kib >> unit && key != "MemAvailable:") {
  }
  if (kib > 60'000'000) {
    WARN("this machine has " << kib / 1'000'000 << " GB available: the 69 GB body would fit");
    return;
  }
  const std::string text =
      replace(replace(replace(kImpact, "min: [-0.01, -0.01, -0.002], max: [0.01, 0.01, 0]",
                              "min: [0, 0, -0.26], max: [0.26, 0.26, 0]"),
                      "contact:\n  stiffness: 1.0e12\n", ""),
              "  - {type: initial_velocity, body: ball, value: [0, 0, -10]}\n",
              "  - {type: initial_velocity, body: ball, value: [0, 0, -1]}\n");
  expect_refused(text, {"case.yaml:5: bodies[0]", "body 'plate' needs at least 69",
                        "1.76e+07 points", "the available memory (MemAvailable)"});
}

TEST_CASE("moduli, densities and stiffnesses outside physical bounds name their key",
          "[hardened]") {
  expect_refused(replace(kPlate, "youngs_modulus: 210e9", "youngs_modulus: 1e300"),
                 {"case.yaml:3:", "materials.steel.youngs_modulus", "magnitude at most 1e30"});
  expect_refused(replace(kPlate, "youngs_modulus: 210e9", "youngs_modulus: 1e20"),
                 {"case.yaml:3:", "materials.steel.youngs_modulus", "Young's modulus in Pa"});
  expect_refused(replace(kPlate, "density: 7580", "density: 1e-20"),
                 {"case.yaml:3:", "materials.steel.density", "density"});
  expect_refused(replace(kImpact, "stiffness: 1.0e12", "stiffness: 1e300"),
                 {"case.yaml:18:", "contact.stiffness", "magnitude at most 1e30"});
  expect_refused(replace(kImpact, "stiffness: 1.0e12", "stiffness: 1e20"),
                 {"case.yaml:18:", "contact.stiffness", "a contact stiffness in Pa"});
}

TEST_CASE("a speed of 1e300, or of light, is refused naming the key", "[hardened]") {
  expect_refused(replace(kImpact, "value: [0, 0, -10]", "value: [0, 0, -1e300]"),
                 {"case.yaml:16:", "conditions[0].value[2]", "magnitude at most 1e30"});
  expect_refused(replace(kImpact, "value: [0, 0, -10]", "value: [0, 0, -3e8]"),
                 {"case.yaml:16:", "conditions[0].value", "a velocity in m/s"});
}

TEST_CASE("an impact faster than the contact can stop is flagged, not completed", "[hardened]") {
  // At 1e6 m/s the contact speed bound cut dt so far that no body moved far per step, and the
  // sphere passed through the plate with no damage; the closing speed is now checked against
  // l_c sqrt(k / rho), the speed the penalty can stop within l_c. The refusal names the line
  // and key of the velocity that sets the closing speed.
  expect_refused(replace(kImpact, "value: [0, 0, -10]", "value: [0, 0, -1e6]"),
                 {"case.yaml:16: conditions[0]: bodies plate/ball close at 1e+06 m/s",
                  "would pass through each other"});
  expect_refused(replace(kImpact, "value: [0, 0, -10]", "value: [0, 0, -2.9e8]"),
                 {"case.yaml:16: conditions[0]: bodies plate/ball close at 2.9e+08 m/s"});
}

TEST_CASE("a time step above the estimate names the file, line and key", "[hardened]") {
  expect_refused(replace(kPlate, "time: {steps: 5}", "time: {steps: 5, dt: 1.0}"),
                 {"case.yaml:11: time.dt = 1 s", "exceeds the stable-step estimate"});
}

namespace {

// A body sampled inside a mesh file (the repository's impactor sphere, 10 mm across).
std::string mesh_case(const std::string& mesh_file) {
  return R"(# a body from a mesh, SI units
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.25}
bodies:
  - name: ball
    material: steel
    geometry: {type: mesh, file: )" +
         mesh_file + R"(, scale: 0.001}
    spacing: 0.002
    horizon_ratio: 3.015
time: {steps: 2}
)";
}

}  // namespace

TEST_CASE("an importer that aborts ends its child process, not ckpd: exit 2", "[hardened][mesh]") {
  const std::string mesh = std::string(CKPD_SOURCE_DIR) + "/cases/meshes/impactor.obj";
  const auto dir = fresh_dir("mesh-abort");
  const std::string file = write_file(dir / "case.yaml", mesh_case(mesh));
  // The same case loads when the importer behaves, so the failure below is the hook's.
  CHECK(run_ckpd("check " + file + " --steps 0").exit_code == 0);
  // The hook makes the import's child abort() as assimp's ai_assert does (OpenGEX camera.ogex).
  setenv("CKPD_TEST_MESH_IMPORT_ABORT", "1", 1);
  const CommandResult r = run_ckpd("run " + file + " --quiet --out " + (dir / "out").string());
  unsetenv("CKPD_TEST_MESH_IMPORT_ABORT");
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("case.yaml:7: bodies[0].geometry.file") != std::string::npos);
  CHECK(r.output.find("assimp's Wavefront Object Importer can read") != std::string::npos);
  CHECK(r.output.find("killed by signal 6") != std::string::npos);
  CHECK(r.output.find("impactor.obj") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir / "out" / "summary.json"));
}

TEST_CASE("an importer that segfaults on a real file ends its child process, not ckpd: exit 2",
          "[hardened][mesh]") {
  // Two groups of triangles in assimp's RAW format: its importer segfaults on them, as on the
  // campaign's RAW/WithColor.raw (under AddressSanitizer the child's SEGV handler aborts
  // instead: a signal either way). No hook: the crash is assimp's own.
  const auto dir = fresh_dir("mesh-segv");
  const std::string mesh =
      write_file(dir / "two_groups.raw", "a\n0 0 0 1 0 0 0 1 0\nb\n0 0 1 1 0 1 0 1 1\n");
  const std::string file = write_file(dir / "case.yaml", mesh_case(mesh));
  const CommandResult r = run_ckpd("run " + file + " --quiet --out " + (dir / "out").string());
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("case.yaml:7: bodies[0].geometry.file") != std::string::npos);
  CHECK(r.output.find("assimp's Raw Importer can read: it was killed by signal") !=
        std::string::npos);
  CHECK(r.output.find("two_groups.raw") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir / "out" / "summary.json"));
}

TEST_CASE("a mesh header claiming 353 billion vertices is refused at once, not read into RAM",
          "[hardened][mesh]") {
  // The campaign's 309-byte invalid/OutOfMemory.off drove RSS past 8 GB in 20 s: an OFF cube
  // whose header counts 353,535,235,358 vertices. The child's allocation fails against its
  // limit (RLIMIT_AS, 8 GiB), and the error names the file and key.
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define CKPD_TEST_UNDER_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(CKPD_TEST_UNDER_ASAN)
  // Under AddressSanitizer the child has no address-space limit (the shadow memory reserves
  // terabytes): assimp's OFF reader then fills memory (the child passed 16 GB of RSS, as if
  // the count were read as 32 bits: 1.35e9 vertices), the campaign's signature. Not run in
  // the sanitizer build.
  WARN("AddressSanitizer build: the mesh import child has no memory limit; skipped");
  return;
#endif
  const auto dir = fresh_dir("mesh-oom");
  std::string off = "OFF\n353535235358 6 0\n";
  for (int k = 0; k < 8; ++k)
    off += std::string(k & 1 ? "1" : "0") + (k & 2 ? " 1" : " 0") + (k & 4 ? " 1\n" : " 0\n");
  off += "4 0 1 3 2\n4 4 6 7 5\n4 0 4 5 1\n4 2 3 7 6\n4 0 2 6 4\n4 1 5 7 3\n";
  const std::string mesh = write_file(dir / "claims_too_many.off", off);
  expect_refused(mesh_case(mesh), {"case.yaml:7: bodies[0].geometry.file", "claims_too_many.off"});
}

TEST_CASE("a mesh file over the size limit is refused before it is read", "[hardened][mesh]") {
  const auto dir = fresh_dir("mesh-size");
  // A sparse 2 GiB STL: no disk space, and nothing is read.
  const auto mesh = dir / "huge.stl";
  { std::ofstream(mesh).put('x'); }
  std::filesystem::resize_file(mesh, std::uintmax_t{2} << 30);
  expect_refused(mesh_case(mesh.string()),
                 {"case.yaml:7: bodies[0].geometry.file", "at most 1024 MiB", "2048 MiB"});
}

TEST_CASE("sweep expressions and sizes past their bounds are refused at once",
          "[hardened][sweep]") {
  const auto dir = fresh_dir("hardened-sweep");
  write_sweep_base(dir);
  auto refused = [&](const std::string& body, const std::string& what) {
    const std::string sweep = write_file(dir / "bad.yaml", "base: base.yaml\n" + body);
    const auto out = dir / "out";
    const CommandResult r = run_ckpd("sweep " + sweep + " --dry-run --out " + out.string());
    INFO(r.output.substr(0, 2000));
    CHECK(r.exit_code == 2);
    CHECK(r.output.find(what) != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(out));
  };
  const std::string dx = "parameters:\n  dx: {key: bodies.block.spacing, values: [0.001]}\n";
  // 20,000 nested parentheses and a 50,000-term sum overflowed the stack.
  refused(
      dx + "  h: {expr: \"" + std::string(20000, '(') + "dx" + std::string(20000, ')') + "\"}\n",
      "bad.yaml:4: parameters.h.expr");
  refused(
      dx + "  h: {expr: \"" + std::string(20000, '(') + "dx" + std::string(20000, ')') + "\"}\n",
      "longer than the limit of 4096");
  refused(dx + "  h: {expr: \"" + std::string(300, '(') + "dx" + std::string(300, ')') + "\"}\n",
          "at most 200 nested levels");
  std::string sum = "dx";
  for (int k = 0; k < 50000; ++k) sum += "+1";
  refused(dx + "  h: {expr: \"" + sum + "\"}\n", "longer than the limit of 4096");
  // A million-run range and a 3000 x 3000 grid took minutes to resolve.
  refused(
      "parameters:\n  dx: {key: bodies.block.spacing, range: {from: 0.001, to: 0.002, count: "
      "1000000}}\n",
      "bad.yaml:3: parameters.dx.range.count: expected a count from 1 to 100000");
  std::string a = "[", b = "[";
  for (int k = 0; k < 3000; ++k) {
    a += (k ? ", " : "") + std::to_string(0.001 + 1e-7 * k);
    b += (k ? ", " : "") + std::to_string(2.0 + 1e-3 * k);
  }
  refused("parameters:\n  dx: {key: bodies.block.spacing, values: " + a +
              "]}\n  m: {key: bodies.block.horizon_ratio, values: " + b + "]}\n",
          "at most 100000 runs (the grid has 9");
}

TEST_CASE("a sweep whose set: or values the case refuses is refused by --dry-run and at start",
          "[hardened][sweep]") {
  // A `set:` key the base case does not have passed --dry-run, then every run failed.
  const auto dir = fresh_dir("hardened-sweep-load");
  write_sweep_base(dir);
  auto refused = [&](const std::string& body, std::initializer_list<std::string> fragments) {
    const std::string sweep = write_file(dir / "bad.yaml", "base: base.yaml\n" + body);
    const auto out = dir / "out";
    for (const std::string args : {" --dry-run", " --quiet"}) {
      const CommandResult r = run_ckpd("sweep " + sweep + " --out " + out.string() + args);
      INFO(args << "\n" << r.output.substr(0, 2000));
      CHECK(r.exit_code == 2);
      for (const std::string& f : fragments) CHECK(r.output.find(f) != std::string::npos);
      CHECK_FALSE(std::filesystem::exists(out));
    }
  };
  const std::string m = "parameters:\n  m: {key: bodies.block.horizon_ratio, values: [3.015, 4]}\n";
  refused("set:\n  bodies.block.spacinx: 0.002\n" + m,
          {"bad.yaml: run 0 (m=3.015) does not load", "bodies.block.spacinx=0.002",
           "bodies[0].spacinx: unknown key 'spacinx' (did you mean 'spacing'?)"});
  refused(
      "set:\n  time.stepz: 5\n" + m,
      {"does not load", "time.stepz=5", "time.stepz: unknown key 'stepz' (did you mean 'steps'?)"});
  // A value out of bounds in one run only.
  refused("parameters:\n  m: {key: bodies.block.horizon_ratio, values: [3.015, 1e4]}\n",
          {"bad.yaml: run 1 (m=1e4) does not load", "bodies[0].horizon_ratio",
           "at most 100000 lattice offsets"});
  // One key set twice in a run: the last value would win silently.
  refused(m + "  dx: {key: bodies.block.horizon_ratio, values: [3]}\n",
          {"bad.yaml:4: parameters.dx.key: 'bodies.block.horizon_ratio' is set by parameter 'm'"});
  refused("set:\n  bodies.block.horizon_ratio: 3\n" + m,
          {"bad.yaml:5: parameters.m.key: 'bodies.block.horizon_ratio' is set by set: already"});
  // A list index past size_t in a parameter key (std::stoul threw: exit 1).
  refused("parameters:\n  dx: {key: bodies.99999999999999999999.spacing, values: [0.001]}\n",
          {"bad.yaml:3: parameters.dx.key: 'bodies.99999999999999999999.spacing' does not exist"});
}

TEST_CASE("a --set list index too long for any list is exit 2 naming it, not stoul's exit 1",
          "[hardened]") {
  const auto dir = fresh_dir("hardened-set-index");
  const std::string file = write_file(dir / "case.yaml", kPlate);
  for (const std::string command : {"check ", "run "}) {
    const CommandResult r =
        run_ckpd(command + file + " --set bodies.99999999999999999999.spacing=1" +
                 (command == "run " ? " --quiet --out " + (dir / "out").string() : ""));
    INFO(r.output);
    CHECK(r.exit_code == 2);
    CHECK(r.output.find("--set bodies.99999999999999999999.spacing: 'bodies' has no element "
                        "'99999999999999999999'") != std::string::npos);
  }
  CHECK_FALSE(std::filesystem::exists(dir / "out"));
}

TEST_CASE("check's timed steps exit 3 on an instability, as run does", "[hardened]") {
  // dt forced to 20 x the stable estimate: the first steps blow up.
  const std::string text = replace(
      replace(kPlate, "time: {steps: 5}", "time: {steps: 50, dt: 3e-5, allow_unstable_dt: true}"),
      "    horizon_ratio: 3.015\n",
      "    horizon_ratio: 3.015\nconditions:\n  - {type: initial_velocity, body: plate, value: [1, "
      "0]}\n");
  const auto dir = fresh_dir("hardened-unstable");
  const std::string file = write_file(dir / "case.yaml", text);
  const CommandResult run = run_ckpd("run " + file + " --quiet --out " + (dir / "out").string());
  INFO(run.output);
  CHECK(run.exit_code == 3);
  const CommandResult check = run_ckpd("check " + file + " --steps 50");
  INFO(check.output);
  CHECK(check.exit_code == 3);
  CHECK(check.output.find("instability at step") != std::string::npos);
}

TEST_CASE("an output folder that cannot be created is exit 2, before any step", "[hardened]") {
  const auto dir = fresh_dir("hardened-out");
  const std::string file = write_file(dir / "case.yaml", kPlate);
  write_file(dir / "a_file", "x");
  const CommandResult r =
      run_ckpd("run " + file + " --quiet --out " + (dir / "a_file" / "out").string());
  INFO(r.output);
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("cannot create the output directory") != std::string::npos);
  // --out naming an existing file (was exit 1).
  const CommandResult f = run_ckpd("run " + file + " --quiet --out " + (dir / "a_file").string());
  INFO(f.output);
  CHECK(f.exit_code == 2);
  CHECK(f.output.find("--out " + (dir / "a_file").string() +
                      ": cannot create the output directory") != std::string::npos);
}

TEST_CASE("SIGTERM during set-up exits 130 with a message and writes nothing", "[hardened]") {
  // 216,000 points with their families: seconds of set-up, interrupted after half a second.
  const std::string text =
      replace(replace(kImpact, "min: [-0.01, -0.01, -0.002], max: [0.01, 0.01, 0]",
                      "min: [-0.03, -0.03, -0.06], max: [0.03, 0.03, 0]"),
              "contact:\n  stiffness: 1.0e12\n", "");
  const auto dir = fresh_dir("hardened-sigterm");
  const std::string file = write_file(dir / "case.yaml", text);
  const auto out = dir / "out";
  const CommandResult r =
      run_ckpd("run " + file + " --quiet --out " + out.string() +
               " 2>&1 & pid=$!; sleep 0.5; kill -TERM $pid; wait $pid; echo exit=$?");
  INFO(r.output);
  CHECK(r.output.find("exit=130") != std::string::npos);
  CHECK(r.output.find("interrupted (SIGTERM) during set-up; nothing was run or written") !=
        std::string::npos);
  CHECK_FALSE(std::filesystem::exists(out));
}

TEST_CASE("SIGTERM while a sweep loads its runs' cases exits 130 with a message",
          "[hardened][sweep]") {
  // The sweep loads each run's case before the first starts (seconds for this block): a signal
  // then killed it silently (exit 143).
  const std::string text =
      replace(replace(kImpact, "min: [-0.01, -0.01, -0.002], max: [0.01, 0.01, 0]",
                      "min: [-0.03, -0.03, -0.06], max: [0.03, 0.03, 0]"),
              "contact:\n  stiffness: 1.0e12\n", "");
  const auto dir = fresh_dir("hardened-sweep-sigterm");
  write_file(dir / "base.yaml", text);
  const std::string sweep =
      write_file(dir / "s.yaml",
                 "base: base.yaml\nparameters:\n  m: {key: bodies.ball.horizon_ratio, "
                 "values: [3.015, 3.5, 4]}\n");
  const auto out = dir / "out";
  const CommandResult r =
      run_ckpd("sweep " + sweep + " --out " + out.string() +
               " 2>&1 & pid=$!; sleep 0.5; kill -TERM $pid; wait $pid; echo exit=$?");
  INFO(r.output);
  CHECK(r.output.find("exit=130") != std::string::npos);
  CHECK(r.output.find("interrupted (SIGTERM) during set-up; nothing was run or written") !=
        std::string::npos);
  CHECK_FALSE(std::filesystem::exists(out));
}

TEST_CASE("a restart after SIGTERM continues the history without a repeated row", "[hardened]") {
  // Moving (a body at rest trips the energy guard on round-off over thousands of steps).
  const std::string text =
      replace(kPlate, "time: {steps: 5}",
              "conditions:\n  - {type: initial_velocity, body: plate, value: [1, 0]}\n"
              "time: {steps: 100000000}\noutput: {history_interval: 7}");
  const auto dir = fresh_dir("hardened-history");
  const std::string file = write_file(dir / "case.yaml", text);
  const auto out = dir / "out";
  const CommandResult r =
      run_ckpd("run " + file + " --quiet --out " + out.string() +
               " 2>&1 & pid=$!; sleep 1.5; kill -TERM $pid; wait $pid; echo exit=$?");
  INFO(r.output);
  REQUIRE(r.output.find("exit=130") != std::string::npos);
  const long long stopped = read_json(out / "summary.json")["steps"];
  for (int restart = 0; restart < 2; ++restart) {
    const CommandResult more = run_ckpd("run " + file + " --quiet --out " + out.string() +
                                        " --restart " + (out / "checkpoint.h5").string() +
                                        " --set time.steps=" + std::to_string(stopped + 20));
    INFO(more.output);
    CHECK(more.exit_code == 0);
  }
  std::ifstream history(out / "history.csv");
  std::string line;
  std::getline(history, line);
  long long previous = -1;
  while (std::getline(history, line)) {
    const long long step = std::stoll(line.substr(0, line.find(',')));
    INFO(line);
    CHECK(step > previous);
    previous = step;
  }
  CHECK(previous == stopped + 20);
}

TEST_CASE("a restart from a checkpoint of the last step repeats no history row", "[hardened]") {
  // The checkpoint interval divides the step count: the checkpoint is of the last step, as when
  // SIGTERM arrives during the last step. Restarting from it (a sweep continues such a run)
  // wrote the last row again.
  const std::string text =
      replace(kPlate, "time: {steps: 5}",
              "conditions:\n  - {type: initial_velocity, body: plate, value: [1, 0]}\n"
              "time: {steps: 20}\noutput: {history_interval: 7, checkpoint_interval: 10}");
  const auto dir = fresh_dir("hardened-history-end");
  const std::string file = write_file(dir / "case.yaml", text);
  const auto out = dir / "out";
  REQUIRE(run_ckpd("run " + file + " --quiet --out " + out.string()).exit_code == 0);
  auto steps = [&] {
    std::ifstream history(out / "history.csv");
    std::string line, list;
    std::getline(history, line);
    while (std::getline(history, line)) list += line.substr(0, line.find(',')) + " ";
    return list;
  };
  CHECK(steps() == "0 7 14 20 ");
  for (int restart = 0; restart < 2; ++restart) {
    const CommandResult r = run_ckpd("run " + file + " --quiet --out " + out.string() +
                                     " --restart " + (out / "checkpoint.h5").string());
    INFO(r.output);
    CHECK(r.exit_code == 0);
    CHECK(steps() == "0 7 14 20 ");
  }
  // From the checkpoint of step 10 (a shorter run that ended there): its off-schedule last row
  // at step 10 is dropped, and the rows are the uninterrupted run's (as after a SIGTERM).
  const CommandResult r =
      run_ckpd("run " + file + " --quiet --out " + out.string() + " --set time.steps=10");
  REQUIRE(r.exit_code == 0);
  CHECK(steps() == "0 7 10 ");
  const CommandResult more = run_ckpd("run " + file + " --quiet --out " + out.string() +
                                      " --restart " + (out / "checkpoint.h5").string());
  INFO(more.output);
  CHECK(more.exit_code == 0);
  CHECK(steps() == "0 7 14 20 ");
}
