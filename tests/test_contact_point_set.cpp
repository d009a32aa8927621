// The contact manager on raw arrays, through the point-set view alone (no body is built): forces
// and energy against an all-pairs sum of MODEL.md section 5, self-contact through the view's
// bond query, the same bits on one and two threads with every loop parallel, and a view cut to
// some points with only some computed (a distributed rank's owned points and contact ghosts).
#include <omp.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <random>
#include <set>
#include <utility>

#include "base/parallel_policy.hpp"
#include "contact/contact_manager.hpp"

using namespace ckpd;

namespace {

constexpr double kLc = 0.5e-3, kStiffness = 1e12, kHorizon = 2e-3, kSpacing = 1e-3;

// Arrays of one point set: a jittered cubic lattice block.
struct RawPoints {
  std::vector<Vec3> reference, displacement, velocity, force;
  std::vector<double> volume;
  std::set<std::pair<std::uint32_t, std::uint32_t>> bonds;  // intact, both orders

  RawPoints(const Vec3& corner, int n, std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-0.3 * kSpacing, 0.3 * kSpacing);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k) {
          reference.push_back(corner + kSpacing * Vec3(i, j, k));
          displacement.emplace_back(u(rng), u(rng), u(rng));
          volume.push_back(kSpacing * kSpacing * kSpacing * (1 + 0.1 * u(rng) / kSpacing));
        }
    velocity.assign(reference.size(), Vec3::Zero());
    force.assign(reference.size(), Vec3::Zero());
  }
  static bool bonded(const void* self, std::uint32_t i, std::uint32_t j) {
    return static_cast<const RawPoints*>(self)->bonds.count({i, j}) > 0;
  }
  PointSet view(const char* name) {
    PointSet p;
    p.name = name;
    p.horizon = kHorizon;
    p.spacing = kSpacing;
    p.density = 7850;
    p.reference = reference;
    p.displacement = displacement;
    p.velocity = velocity;
    p.volume = volume;
    p.force_density = force;
    p.bonds = {this, bonded};
    return p;
  }
  Vec3 x(std::size_t i) const { return reference[i] + displacement[i]; }
};

ContactSettings settings(bool self_on_first) {
  ContactSettings s;
  s.present = true;
  s.global.stiffness = kStiffness;
  s.global.radius = kLc;
  if (self_on_first) s.self_contact.push_back(0);
  return s;
}

// All pairs: F^i = c (l_c - r) (x^i - x^j)/r V^i V^j, U = c V^i V^j (l_c - r)^2 / 2.
double all_pairs(const std::vector<RawPoints*>& sets, bool self_on_first,
                 std::vector<std::vector<Vec3>>& force) {
  const double c = 9 * kStiffness / (M_PI * std::pow(kHorizon, 5));
  double energy = 0;
  force.clear();
  for (const RawPoints* s : sets) force.emplace_back(s->reference.size(), Vec3::Zero());
  for (std::size_t a = 0; a < sets.size(); ++a)
    for (std::size_t b = a; b < sets.size(); ++b) {
      if (a == b && !(a == 0 && self_on_first)) continue;
      const RawPoints& A = *sets[a];
      const RawPoints& B = *sets[b];
      for (std::size_t i = 0; i < A.reference.size(); ++i)
        for (std::size_t j = a == b ? i + 1 : 0; j < B.reference.size(); ++j) {
          if (a == b &&
              A.bonds.count({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j)}))
            continue;
          const Vec3 d = A.x(i) - B.x(j);
          const double r = d.norm();
          if (r >= kLc) continue;
          force[a][i] += c * (kLc - r) / r * B.volume[j] * d;
          force[b][j] -= c * (kLc - r) / r * A.volume[i] * d;
          energy += 0.5 * c * A.volume[i] * B.volume[j] * (kLc - r) * (kLc - r);
        }
    }
  return energy;
}

// Three blocks, the second and third pressed into the first; bonds of the first between lattice
// neighbours, a third of them failed.
struct Blocks {
  std::mt19937 rng{17};
  RawPoints a{Vec3::Zero(), 5, rng}, b{Vec3(4.6e-3, 0.3e-3, 0), 4, rng},
      c{Vec3(0.2e-3, 4.55e-3, 0.1e-3), 4, rng};
  Blocks() {
    for (std::uint32_t i = 0; i < a.reference.size(); ++i)
      for (std::uint32_t j = 0; j < i; ++j)
        if ((a.reference[i] - a.reference[j]).norm() < 1.5 * kSpacing && rng() % 3) {
          a.bonds.insert({i, j});
          a.bonds.insert({j, i});
        }
  }
  std::vector<ContactBody> bodies() {
    std::vector<ContactBody> v(3);
    v[0].points = a.view("a");
    v[1].points = b.view("b");
    v[2].points = c.view("c");
    return v;
  }
};

}  // namespace

TEST_CASE("contact on raw point arrays equals the all-pairs sum, self-contact by the bond query",
          "[contact][point_set]") {
  for (bool self : {false, true}) {
    Blocks blocks;
    ContactManager manager(blocks.bodies(), settings(self));
    manager.add_forces();
    std::vector<std::vector<Vec3>> reference;
    const double energy = all_pairs({&blocks.a, &blocks.b, &blocks.c}, self, reference);
    const RawPoints* sets[] = {&blocks.a, &blocks.b, &blocks.c};
    double largest = 0;
    for (const auto& f : reference)
      for (const Vec3& v : f) largest = std::max(largest, v.norm());
    REQUIRE(largest > 0);
    for (int s = 0; s < 3; ++s)
      for (std::size_t i = 0; i < reference[s].size(); ++i)
        REQUIRE((sets[s]->force[i] - reference[s][i]).norm() <= 1e-12 * largest);
    CHECK(manager.energy() == Approx(energy).epsilon(1e-12));
    CHECK(manager.statistics().touching_pairs >= 2u);  // a-b and a-c; a-a when a gap is open
  }
}

TEST_CASE("a rebind to moved arrays is what the next evaluation reads", "[contact][point_set]") {
  Blocks blocks;
  ContactManager manager(blocks.bodies(), settings(false));
  manager.add_forces();
  // Replace b's arrays by copies moved 3 mm away: no contact with them, none left.
  RawPoints moved = blocks.b;
  for (Vec3& u : moved.displacement) u.x() += 3e-3;
  std::vector<PointSet> views = {blocks.a.view("a"), moved.view("b"), blocks.c.view("c")};
  manager.rebind(views);
  std::fill(moved.force.begin(), moved.force.end(), Vec3::Zero());
  manager.add_forces();
  for (const Vec3& f : moved.force) REQUIRE(f.isZero());
  views[1].reference = views[1].reference.first(3);
  CHECK_THROWS_AS(manager.rebind(views), std::invalid_argument);
}

TEST_CASE("contact on raw arrays gives the same bits on one and two threads, loops parallel",
          "[contact][point_set]") {
  const ScopedParallelThresholds every_loop_parallel(0);
  const int before = omp_get_max_threads();
  std::vector<Vec3> result[2][3];
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    Blocks blocks;
    ContactManager manager(blocks.bodies(), settings(true));
    manager.add_forces();
    result[threads - 1][0] = blocks.a.force;
    result[threads - 1][1] = blocks.b.force;
    result[threads - 1][2] = blocks.c.force;
  }
  omp_set_num_threads(before);
  for (int s = 0; s < 3; ++s) REQUIRE(result[0][s] == result[1][s]);
}

namespace {

// A view of `from` cut to the points `keep` (increasing), computed where `computed` says: what a
// rank hands contact on distributed memory (its owned points and its contact ghosts).
struct CutPoints {
  RawPoints points;
  std::vector<std::uint8_t> computed;
  CutPoints(const RawPoints& from, const std::vector<std::uint32_t>& keep,
            const std::vector<std::uint8_t>& computed_of_from)
      : points(from) {
    points.reference.clear();
    points.displacement.clear();
    points.velocity.clear();
    points.force.clear();
    points.volume.clear();
    points.bonds.clear();
    std::vector<std::int64_t> at(from.reference.size(), -1);
    for (std::uint32_t i : keep) {
      at[i] = static_cast<std::int64_t>(points.reference.size());
      points.reference.push_back(from.reference[i]);
      points.displacement.push_back(from.displacement[i]);
      points.velocity.push_back(from.velocity[i]);
      points.force.push_back(Vec3::Zero());
      points.volume.push_back(from.volume[i]);
      computed.push_back(computed_of_from[i]);
    }
    for (const auto& [i, j] : from.bonds)
      if (at[i] >= 0 && at[j] >= 0)
        points.bonds.insert({static_cast<std::uint32_t>(at[i]), static_cast<std::uint32_t>(at[j])});
  }
  PointSet view(const char* name) {
    PointSet p = points.view(name);
    p.computed = computed;
    return p;
  }
};

}  // namespace

TEST_CASE(
    "points outside `computed` are partners only: a cut view gives the computed points the "
    "whole view's forces bit for bit and the energies of two halves add up",
    "[contact][point_set]") {
  const int before = omp_get_max_threads();
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    const ScopedParallelThresholds every_loop_parallel(threads == 2 ? 0 : 1000000);
    Blocks whole;
    ContactManager all(whole.bodies(), settings(true));
    all.add_forces();
    const RawPoints* sets[] = {&whole.a, &whole.b, &whole.c};
    // Two "ranks" split space at y = 2.2 mm; each keeps its own points and every point of the
    // others within l_c + 1 mm of one of them (more than the contact reach), in index order.
    double energy = 0;
    for (int side = 0; side < 2; ++side) {
      std::vector<std::unique_ptr<CutPoints>> cut;
      std::vector<std::size_t> computed_count(3, 0), cut_size(3, 0);
      for (int s = 0; s < 3; ++s) {
        const RawPoints& from = *sets[s];
        std::vector<std::uint8_t> mine(from.reference.size());
        for (std::size_t i = 0; i < mine.size(); ++i)
          mine[i] = (from.x(i).y() < 2.2e-3) == (side == 0) ? 1 : 0;
        std::vector<std::uint32_t> keep;
        for (std::uint32_t i = 0; i < from.reference.size(); ++i) {
          bool near = mine[i] != 0;
          for (int t = 0; t < 3 && !near; ++t)
            for (std::size_t j = 0; j < sets[t]->reference.size() && !near; ++j) {
              const bool theirs_mine = (sets[t]->x(j).y() < 2.2e-3) == (side == 0);
              near = theirs_mine && (sets[t]->x(j) - from.x(i)).norm() < kLc + 1e-3;
            }
          if (near) keep.push_back(i);
        }
        cut.push_back(std::make_unique<CutPoints>(from, keep, mine));
        cut_size[s] = keep.size();
        for (std::uint32_t i : keep) computed_count[s] += mine[i];
      }
      // The cut must leave points out, and hold points it does not compute.
      REQUIRE(cut_size[0] < whole.a.reference.size());
      REQUIRE(cut_size[0] > computed_count[0]);
      std::vector<ContactBody> bodies(3);
      bodies[0].points = cut[0]->view("a");
      bodies[1].points = cut[1]->view("b");
      bodies[2].points = cut[2]->view("c");
      ContactManager part(bodies, settings(true));
      part.add_forces();
      energy += part.energy();
      for (int s = 0; s < 3; ++s) {
        const RawPoints& from = *sets[s];
        std::size_t k = 0;
        for (std::uint32_t i = 0; i < from.reference.size(); ++i) {
          if (k == cut[s]->points.reference.size() ||
              cut[s]->points.reference[k] != from.reference[i])
            continue;
          if (cut[s]->computed[k])
            REQUIRE(cut[s]->points.force[k] == from.force[i]);  // the same bits
          else
            REQUIRE(cut[s]->points.force[k].isZero());  // a partner only
          ++k;
        }
        REQUIRE(k == cut[s]->points.reference.size());
      }
    }
    CHECK(energy == Approx(all.energy()).epsilon(1e-13));
    CHECK(all.energy() > 0);
  }
  omp_set_num_threads(before);
}

TEST_CASE("a view without points takes no part in contact (a rank's empty share of a body)",
          "[contact][point_set]") {
  Blocks with, without;
  ContactManager three(with.bodies(), settings(true));
  three.add_forces();
  // The same scene with the third body's view cut to no points: the first two bodies' forces
  // are those of the scene without it.
  RawPoints none = without.c;
  none.reference.clear();
  none.displacement.clear();
  none.velocity.clear();
  none.force.clear();
  none.volume.clear();
  std::vector<ContactBody> bodies(3);
  bodies[0].points = without.a.view("a");
  bodies[1].points = without.b.view("b");
  bodies[2].points = none.view("c");
  ContactManager cut(bodies, settings(true));
  cut.add_forces();
  std::vector<ContactBody> two(2);
  Blocks alone;
  two[0].points = alone.a.view("a");
  two[1].points = alone.b.view("b");
  ContactManager pair(two, settings(true));
  pair.add_forces();
  REQUIRE(without.a.force == alone.a.force);
  REQUIRE(without.b.force == alone.b.force);
  CHECK(cut.energy() == pair.energy());
  CHECK(three.energy() > pair.energy());  // c touches a in the whole scene
  // An empty view beside one body alone (at 3 ranks a 2D scene's rank held no point of one plate
  // and FCL met an inverted box).
  std::vector<ContactBody> lone(2);
  lone[0].points = none.view("c");
  lone[1].points = alone.a.view("a");
  ContactManager beside(lone, settings(true));
  beside.add_forces();
  CHECK(beside.energy() >= 0);
}
