// No allocation inside a time step. This program replaces the global operator new (all its
// forms), which is why it is a program of its own: the replacement is program-wide. A small scene
// (a pre-cracked 3D CKPD block, bonds, triangles and tetrahedra, struck by a rigid sphere, so
// that contact acts and bonds break while it is counted) runs some steps to warm up (the first
// contact, the first failures size the buffers), then every further step must allocate nothing.
#include <execinfo.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <new>
#include <string>

#include "run_helpers.hpp"
#include "src/case/case_loader.hpp"
#include "src/engine/simulation.hpp"

namespace {

std::atomic<bool> counting{false};
std::atomic<long long> allocations{0};
// With CKPD_ALLOC_TRACE set, where the allocations seen while counting came from (the first
// kTraced call stacks, printed after the count), to find them.
constexpr int kTraced = 64, kFrames = 8;
void* traced_frames[kTraced][kFrames];
int traced_depth[kTraced];
std::atomic<int> traced{0};
const bool trace = std::getenv("CKPD_ALLOC_TRACE") != nullptr;

void count_one() {
  if (!counting.load(std::memory_order_relaxed)) return;
  allocations.fetch_add(1, std::memory_order_relaxed);
  if (!trace) return;
  const int k = traced.fetch_add(1);
  if (k < kTraced) traced_depth[k] = backtrace(traced_frames[k], kFrames);
}

void print_traces() {
  const int n = std::min(traced.load(), kTraced);
  for (int k = 0; k < n; ++k) {
    const char line[] = "---- allocation\n";
    const ssize_t w = write(STDERR_FILENO, line, sizeof line - 1);
    (void)w;
    backtrace_symbols_fd(traced_frames[k], traced_depth[k], STDERR_FILENO);  // malloc, not new
  }
}

void* allocate(std::size_t size) {
  count_one();
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}

void* allocate_aligned(std::size_t size, std::size_t alignment) {
  count_one();
  void* p = nullptr;
  if (posix_memalign(&p, alignment < sizeof(void*) ? sizeof(void*) : alignment,
                     size == 0 ? 1 : size) == 0)
    return p;
  throw std::bad_alloc();
}

}  // namespace

void* operator new(std::size_t size) {
  return allocate(size);
}
void* operator new[](std::size_t size) {
  return allocate(size);
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return allocate(size);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return allocate(size);
  } catch (...) {
    return nullptr;
  }
}
void* operator new(std::size_t size, std::align_val_t a) {
  return allocate_aligned(size, static_cast<std::size_t>(a));
}
void* operator new[](std::size_t size, std::align_val_t a) {
  return allocate_aligned(size, static_cast<std::size_t>(a));
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete(void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept {
  std::free(p);
}

namespace {

// 7 x 7 x 7 points, spacing 1 mm, horizon 3.015 mm; nu = 0.3: bonds, triangles and tetrahedra;
// a rigid sphere pressed into its top at 50 m/s. With `damage`, a notch (pre-crack) through half
// the block and Gc low enough that the contact breaks bonds within the first steps. With
// `friction`, the sphere is a free deformable one that hits obliquely under linear_dashpot with
// Coulomb friction (tangential springs, the clusters that take up the couples).
// With `bonds_only`, nu = 1/4: the block has bonds only (the bond-only kernel, which fails its
// bonds in its own pass: bodies/symmetric/bond_only.hpp).
std::string case_text(bool fracture, bool friction = false, bool bonds_only = false) {
  const std::string striker = friction ? R"(  - name: striker
    material: steel
    geometry: {type: sphere, center: [0.0035, 0.0035, 0.0094], radius: 0.0025}
    spacing: 0.001
    horizon_ratio: 3.015
conditions:
  - {type: initial_velocity, body: striker, value: [30, 10, -50]}
contact:
  stiffness: 1.0e12
  radius: 0.00075
  law: linear_dashpot
  restitution: 0.5
  friction: 0.4
)"
                                       : R"(  - name: striker
    material: steel
    rigid: {motion: prescribed, velocity: [0, 0, -50]}
    geometry: {type: sphere, center: [0.0035, 0.0035, 0.00945], radius: 0.0025}
    spacing: 0.0005
contact:
  stiffness: 1.0e12
  radius: 0.00075
)";
  return std::string(R"(materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: )") +
         (bonds_only ? "0.25" : "0.3") + (fracture ? ", fracture_energy: 50" : "") + R"(}
bodies:
  - name: block
    material: steel
    dimension: 3
    geometry: {type: box, min: [0, 0, 0], max: [0.007, 0.007, 0.007]}
    spacing: 0.001
    horizon_ratio: 3.015
)" +
         (fracture ? R"(    precracks:
      - [[0.0035, -0.001, 0.0035], [0.0035, 0.008, 0.0035], [0.0035, 0.008, 0.008], [0.0035, -0.001, 0.008]]
)"
                   : "") +
         striker + R"(time: {end: 1.0e-4, dt: auto}
output: {history_interval: 1000000}
)";
}

struct Count {
  long long most_in_one_step = 0;  // steps without energy
  long long with_energy = 0;       // all steps with energy together
  std::size_t broken_before = 0, broken_after = 0, precracked = 0;
  double contact_energy = 0, friction_before = 0, friction_after = 0;
};

// 40 steps to warm up, then 40 counted (every tenth with energy, as a history row's step).
Count count_allocations(bool fracture, bool friction = false, bool bonds_only = false) {
  using namespace ckpd::testing;
  const auto dir = fresh_dir("step-allocations");
  ckpd::Scene scene =
      ckpd::load_scene(write_file(dir / "case.yaml", case_text(fracture, friction, bonds_only)));
  ckpd::Simulation sim(scene);
  const int warm_up = 40, counted = 40;
  for (int k = 0; k < warm_up; ++k) sim.advance(k + 1 == warm_up);
  Count c;
  c.broken_before = sim.broken_bonds();
  c.precracked = sim.precracked_bonds(0);
  c.friction_before = sim.energies().contact_friction;
  traced = 0;
  for (int k = 0; k < counted; ++k) {
    const bool with_energy = k % 10 == 9;
    allocations = 0;
    counting = true;
    sim.advance(with_energy);
    counting = false;
    if (with_energy)
      c.with_energy += allocations;
    else
      c.most_in_one_step = std::max(c.most_in_one_step, allocations.load());
  }
  if (trace) print_traces();
  c.broken_after = sim.broken_bonds();
  c.contact_energy = sim.energies().contact;
  c.friction_after = sim.energies().contact_friction;
  return c;
}

}  // namespace

TEST_CASE("a time step of a 3D body in contact allocates nothing after warm-up", "[allocation]") {
  const Count c = count_allocations(false);
  INFO("contact energy " << c.contact_energy);
  CHECK(c.contact_energy > 0);  // the steps counted were steps in contact
  CHECK(c.most_in_one_step == 0);
  CHECK(c.with_energy == 0);
}

// A damaged body (pre-cracked, bonds breaking): bodies/bond_failure.hpp's failure pass and its
// booking keep their flags, point lists, energies, scratch and displacement copy between steps.
TEST_CASE("a time step of a damaged 3D body in contact, bonds breaking, allocates nothing",
          "[allocation]") {
  const Count c = count_allocations(true);
  INFO("broken bonds " << c.broken_before << " -> " << c.broken_after << ", contact energy "
                       << c.contact_energy);
  // The steps counted were steps of a damaged body in contact, with bonds still breaking.
  REQUIRE(c.broken_after > c.broken_before);
  REQUIRE(c.broken_before > 0);
  REQUIRE(c.precracked > 0);
  REQUIRE(c.contact_energy > 0);
  CHECK(c.most_in_one_step == 0);
  CHECK(c.with_energy == 0);
}

// The same with bonds only (nu = 1/4): the bond-only kernel fails and books its bonds in its own
// pass, with flags kept in the kernel's workspace between steps.
TEST_CASE("a time step of a damaged bond-only 3D body, bonds breaking, allocates nothing",
          "[allocation]") {
  const Count c = count_allocations(true, false, true);
  INFO("broken bonds " << c.broken_before << " -> " << c.broken_after << ", contact energy "
                       << c.contact_energy);
  REQUIRE(c.broken_after > c.broken_before);
  REQUIRE(c.broken_before > 0);
  REQUIRE(c.contact_energy > 0);
  CHECK(c.most_in_one_step == 0);
  CHECK(c.with_energy == 0);
}

// Two deformable bodies in frictional contact: the tangential springs' lists and the clusters
// that take up each contact's couple (contact/point_cluster.hpp) allocate nothing in a step.
TEST_CASE("a time step of two 3D bodies in frictional contact allocates nothing after warm-up",
          "[allocation]") {
  const Count c = count_allocations(false, true);
  INFO("friction work " << c.friction_before << " -> " << c.friction_after);
  // Friction worked during the steps counted (the sphere is in contact from step 16 to 70).
  REQUIRE(c.friction_after > c.friction_before);
  REQUIRE(c.friction_before > 0);
  CHECK(c.most_in_one_step == 0);
  CHECK(c.with_energy == 0);
}
