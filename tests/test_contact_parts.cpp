// The contact manager's parts against plain definitions: forces and energy against an all-pairs
// sum, the skin rule for rebuilds, thread-count independence, no narrow-phase work for boxes that
// never overlap, and the lattice-site count the stable step uses.
#include <omp.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "base/parallel_policy.hpp"
#include "contact/contact_manager.hpp"
#include "contact/contact_stiffness.hpp"
#include "contact_fixtures.hpp"
#include "src/engine/contact_coupling.hpp"

using namespace ckpd;
using namespace ckpd::testing;

namespace {

const char* kSteel =
    "materials:\n  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.25}\n";

// Three overlapping spheres; `extra` is appended to the contact section.
Scene three_spheres(const std::string& extra = "") {
  std::string text = kSteel;
  text += "bodies:\n";
  text += sphere_body("a", "steel", 0, 0, 0, 0.0025, 0.001);
  text += sphere_body("b", "steel", 0.0042, 0, 0, 0.0025, 0.001);
  text += sphere_body("c", "steel", 0.0021, 0.004, 0.0003, 0.0025, 0.001);
  text += "contact: {stiffness: 1.0e12, radius: 0.0005, skin: 0.0004";
  text += extra;
  text += "}\ntime: {steps: 1}\n";
  return scene_from_text("three", text);
}

void jitter(Scene& scene, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  for (SceneBody& sb : scene.bodies)
    for (Vec3& d : sb.body.displacement) d += Vec3(u(rng), u(rng), u(rng));
}

void clear_forces(Scene& scene) {
  for (SceneBody& sb : scene.bodies)
    std::fill(sb.body.force_density.begin(), sb.body.force_density.end(), Vec3::Zero());
}

bool intact(const Body& b, std::size_t i, std::size_t j) {
  for (std::size_t k = b.family.offset[i]; k < b.family.offset[i + 1]; ++k)
    if (b.family.neighbour[k] == j) return b.bond_intact[k];
  return false;
}

// Force densities and energy of THEORY.md section 5 from every pair of points.
struct Reference {
  std::vector<std::vector<Vec3>> force;
  double energy = 0;
};

Reference all_pairs(const Scene& scene, bool self_contact_on_first) {
  const double lc = 0.0005, stiffness = 1.0e12;
  Reference ref;
  for (const SceneBody& sb : scene.bodies) ref.force.emplace_back(sb.body.size(), Vec3::Zero());
  for (std::size_t a = 0; a < scene.bodies.size(); ++a)
    for (std::size_t b = a; b < scene.bodies.size(); ++b) {
      if (a == b && !(a == 0 && self_contact_on_first)) continue;
      const Body& A = scene.bodies[a].body;
      const Body& B = scene.bodies[b].body;
      const double c = contact_coefficient(stiffness, A.horizon);
      for (std::size_t i = 0; i < A.size(); ++i)
        for (std::size_t j = a == b ? i + 1 : 0; j < B.size(); ++j) {
          if (a == b && intact(A, i, j)) continue;
          const Vec3 d = A.current_position(i) - B.current_position(j);
          const double r = d.norm();
          if (r >= lc) continue;
          ref.force[a][i] += c * (lc - r) / r * B.volume[j] * d;
          ref.force[b][j] -= c * (lc - r) / r * A.volume[i] * d;
          ref.energy += 0.5 * c * A.volume[i] * B.volume[j] * (lc - r) * (lc - r);
        }
    }
  return ref;
}

void check_against_all_pairs(const Scene& scene, const ContactManager& manager, bool self) {
  const Reference ref = all_pairs(scene, self);
  double largest = 0;
  for (const auto& f : ref.force)
    for (const Vec3& v : f) largest = std::max(largest, v.norm());
  REQUIRE(largest > 0);
  for (std::size_t b = 0; b < scene.bodies.size(); ++b)
    for (std::size_t i = 0; i < scene.bodies[b].body.size(); ++i)
      REQUIRE((scene.bodies[b].body.force_density[i] - ref.force[b][i]).norm() <= 1e-12 * largest);
  CHECK(manager.energy() == Approx(ref.energy).epsilon(1e-12));
}

}  // namespace

TEST_CASE(
    "contact forces and energy equal the all-pairs sum, before and after moves within the skin",
    "[contact]") {
  Scene scene = three_spheres();
  jitter(scene, 0.0002, 1);
  ContactManager manager(contact_bodies(scene), scene.contact);
  clear_forces(scene);
  manager.add_forces();
  check_against_all_pairs(scene, manager, false);
  CHECK(manager.statistics().rebuilds == 1);
  CHECK(manager.statistics().candidate_pairs == 3);
  CHECK(manager.statistics().touching_pairs == 3);
  CHECK(manager.statistics().points_in_contact > 10);

  // Every point moves less than half the skin (0.2 mm): the candidates still hold.
  jitter(scene, 0.0001, 2);
  clear_forces(scene);
  manager.add_forces();
  CHECK(manager.statistics().rebuilds == 1);
  check_against_all_pairs(scene, manager, false);

  // Further than half the skin: a rebuild, and still the same forces.
  jitter(scene, 0.0004, 3);
  clear_forces(scene);
  manager.add_forces();
  CHECK(manager.statistics().rebuilds == 2);
  check_against_all_pairs(scene, manager, false);
}

TEST_CASE("self-contact repels a body's own points that no intact bond joins", "[contact]") {
  Scene scene = three_spheres(", self_contact: [a]");
  Body& a = scene.bodies[0].body;
  // Fail a third of a's bonds, both directions of each, so that some neighbours are unbonded.
  std::mt19937 rng(5);
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t k = a.family.offset[i]; k < a.family.offset[i + 1]; ++k) {
      const std::uint32_t j = a.family.neighbour[k];
      if (j < i || rng() % 3) continue;
      a.bond_intact[k] = 0;
      for (std::size_t q = a.family.offset[j]; q < a.family.offset[j + 1]; ++q)
        if (a.family.neighbour[q] == i) a.bond_intact[q] = 0;
    }
  jitter(scene, 0.0003, 7);
  ContactManager manager(contact_bodies(scene), scene.contact);
  clear_forces(scene);
  manager.add_forces();
  check_against_all_pairs(scene, manager, true);
}

TEST_CASE("the broad phase rebuilds only when a point has moved more than half the skin",
          "[contact]") {
  Scene scene = three_spheres();
  ContactManager manager(contact_bodies(scene), scene.contact);
  // Body b moves 0.3 skin per call: rebuilds at calls 0, 2, 4, 6, 8.
  for (int call = 0; call < 10; ++call) {
    if (call > 0)
      for (Vec3& d : scene.bodies[1].body.displacement) d.x() += 0.3 * 0.0004;
    manager.add_forces();
  }
  CHECK(manager.statistics().rebuilds == 5);
}

TEST_CASE("contact forces are the same bits on one and on two threads", "[contact]") {
  std::vector<std::vector<Vec3>> result[2];
  const int threads_before = omp_get_max_threads();
  // The scene is small: without this every loop would stay serial on two threads too.
  const ScopedParallelThresholds every_loop_parallel(0);
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    Scene scene = three_spheres(", self_contact: [b]");
    jitter(scene, 0.0003, 11);
    ContactManager manager(contact_bodies(scene), scene.contact);
    clear_forces(scene);
    manager.add_forces();
    for (const SceneBody& sb : scene.bodies) result[threads - 1].push_back(sb.body.force_density);
  }
  omp_set_num_threads(threads_before);
  for (std::size_t b = 0; b < result[0].size(); ++b)
    for (std::size_t i = 0; i < result[0][b].size(); ++i)
      REQUIRE(result[0][b][i] == result[1][b][i]);
}

TEST_CASE("bodies whose boxes never overlap cost no narrow-phase work", "[contact]") {
  // Two spheres 20 mm apart moving apart: the boxes (grown by about a millimetre) never meet.
  std::string text = kSteel;
  text += "bodies:\n";
  text += sphere_body("a", "steel", 0, 0, 0, 0.0025, 0.001);
  text += sphere_body("b", "steel", 0.02, 0, 0, 0.0025, 0.001);
  text +=
      "conditions:\n"
      "  - {type: initial_velocity, body: a, value: [-5, 0, 0]}\n"
      "  - {type: initial_velocity, body: b, value: [5, 3, 0]}\n"
      "contact: {stiffness: 1.0e12, radius: 0.0005}\ntime: {steps: 200}\n";
  Scene scene = scene_from_text("apart", text);
  Simulation sim(scene);
  while (sim.step() < sim.planned_steps()) sim.advance(false);
  REQUIRE(sim.contact() != nullptr);
  const ContactStatistics& s = sim.contact()->statistics();
  CHECK(s.rebuilds >= 1);
  CHECK(s.pairs_checked == 0);
  CHECK(s.points_binned == 0);
  CHECK(s.point_pair_tests == 0);
  CHECK(sim.energies().contact == 0);
}

TEST_CASE("one body without self-contact does no contact work at all", "[contact]") {
  std::string text = kSteel;
  text += "bodies:\n";
  text += sphere_body("a", "steel", 0, 0, 0, 0.0025, 0.001);
  text += "contact: {stiffness: 1.0e12}\ntime: {steps: 2}\n";
  Scene scene = scene_from_text("alone", text);
  Simulation sim(scene);
  CHECK(sim.contact() == nullptr);
}

TEST_CASE("candidate pairs follow the bodies that touch, not the number of bodies", "[contact]") {
  // 24 spheres in a row: 3 mm apart they touch their neighbours only (23 pairs); 10 mm apart
  // nothing overlaps.
  for (double gap : {0.0029, 0.01}) {
    std::string text = kSteel;
    text += "bodies:\n";
    for (int k = 0; k < 24; ++k) {
      std::string name = "s";
      name += std::to_string(k);
      text += sphere_body(name, "steel", k * gap, 0, 0, 0.0015, 0.001);
    }
    text += "contact: {stiffness: 1.0e12, radius: 0.0005}\ntime: {steps: 1}\n";
    Scene scene = scene_from_text("row", text);
    ContactManager manager(contact_bodies(scene), scene.contact);
    manager.add_forces();
    CHECK(manager.statistics().candidate_pairs == (gap < 0.005 ? 23u : 0u));
  }
}

TEST_CASE("lattice sites in a ball: the contact partners the stable step allows for", "[contact]") {
  // A ball of diameter dx holds the two ends of a lattice edge and no more.
  CHECK(max_lattice_sites_in_ball(0.5, 1.0, 3) == 2);
  CHECK(max_lattice_sites_in_ball(0.5, 1.0, 2) == 2);
  // Radius 0.75: a face (radius 0.707); radius 1: a cube's corners (radius 0.866).
  CHECK(max_lattice_sites_in_ball(0.75, 1.0, 3) == 4);
  CHECK(max_lattice_sites_in_ball(1.0, 1.0, 3) == 8);
  // Never fewer than any placement holds.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  for (double radius : {0.5, 0.8, 1.3, 2.2}) {
    const std::size_t bound = max_lattice_sites_in_ball(radius, 1.0, 3);
    for (int trial = 0; trial < 200; ++trial) {
      const Vec3 c(u(rng), u(rng), u(rng));
      std::size_t count = 0;
      for (int i = -4; i <= 4; ++i)
        for (int j = -4; j <= 4; ++j)
          for (int k = -4; k <= 4; ++k)
            if ((Vec3(i, j, k) - c).norm() <= radius) ++count;
      REQUIRE(count <= bound);
    }
  }
}
