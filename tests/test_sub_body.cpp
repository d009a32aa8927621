// A body restricted to a core and its halo (bodies/sub_body.hpp, issue 14's distributed memory):
// the kernel run on each part's restriction with owned_centres = the part's core gives the kept
// points the whole body's partial forces for that core bit for bit at one thread, and the parts'
// partial forces summed over the parts give the whole body's forces and energies to 1e-12 at 1
// and 2 threads: 2D and 3D, lattice stencil and general path, jittered clouds, both damage rules,
// both force forms, with failed bonds; for slabs and for a random point-by-point ownership (the
// largest halos). Bond failure decided on a restriction breaks the same bonds as on the body.
#include <omp.h>

#include <catch2/catch.hpp>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "bodies/damage.hpp"
#include "bodies/sub_body.hpp"
#include "bodies/symmetric_kernel.hpp"
#include "kernel_comparison.hpp"

using namespace kernel_comparison;
using ckpd::DamageRule;
using ckpd::ForceForm;

namespace {

struct Variant {
  ForceForm form;
  DamageRule rule;
  bool stencil;
};

Body make(const Scene& s, const Variant& v, std::mt19937& rng) {
  BodyDefinition d = block(s.dimension, s.nx, s.ny, s.nz, constants_for(s), s.jitter, rng, s.m);
  if (v.form == ForceForm::energy_consistent) vary_volumes(d, rng);
  d.force_form = v.form;
  d.damage_rule = v.rule;
  d.lattice_stencil = v.stencil;
  Body body = ckpd::make_body(d);
  REQUIRE(ckpd::uses_lattice_stencil(body) == (v.stencil && s.jitter == 0));
  perturb(body, 0.05, rng);
  fail_bonds(body, 0.15, rng);
  return body;
}

// Owner of each point: `parts` slabs along x, or chosen at random point by point.
std::vector<int> owners(const Body& body, int parts, bool random, std::mt19937& rng) {
  std::vector<int> owner(body.size());
  double lo = 1e300, hi = -1e300;
  for (const Vec3& p : body.reference_position) {
    lo = std::min(lo, p.x());
    hi = std::max(hi, p.x());
  }
  std::uniform_int_distribution<int> pick(0, parts - 1);
  for (std::size_t i = 0; i < body.size(); ++i) {
    const double t = (body.reference_position[i].x() - lo) / (hi - lo);
    owner[i] = random ? pick(rng) : std::min(parts - 1, static_cast<int>(t * parts));
  }
  return owner;
}

std::vector<std::uint8_t> core_of(const std::vector<int>& owner, int part) {
  std::vector<std::uint8_t> core(owner.size());
  for (std::size_t i = 0; i < owner.size(); ++i) core[i] = owner[i] == part ? 1 : 0;
  return core;
}

// Part `part`'s restriction, its core as owned_centres.
// A critical stretch of 0.02 with the bonds past it failed, then a perturbation to stretches of
// about 0.06 (a share of the bonds about to fail) and random velocities (the booking's midpoint).
// Returns the failed bonds before the perturbation.
std::size_t overstretch(Body& body, std::mt19937& rng) {
  body.critical_stretch = 0.02;
  ckpd::update_bond_failure(body);
  const std::size_t before = ckpd::failed_bond_count(body);
  perturb(body, 0.03, rng);
  std::uniform_real_distribution<double> speed(-1, 1);  // m/s
  for (Vec3& v : body.velocity) v = Vec3(speed(rng), speed(rng), speed(rng));
  return before;
}

// The restriction's bond flags that differ from the whole body's (of its booked points' rows
// only, with `booked_only`).
std::size_t differing_flags(const Body& body, const ckpd::BodyRestriction& r, bool booked_only) {
  std::size_t differing = 0;
  for (std::size_t k = 0; k < r.global.size(); ++k) {
    if (booked_only && !r.body.books(k)) continue;
    std::size_t e = body.family.offset[r.global[k]];
    for (std::size_t l = r.body.family.offset[k]; l < r.body.family.offset[k + 1]; ++l) {
      while (body.family.neighbour[e] != r.global[r.body.family.neighbour[l]]) ++e;
      differing += r.body.bond_intact[l] != body.bond_intact[e];
    }
  }
  return differing;
}

ckpd::BodyRestriction part_restriction(const Body& body, const std::vector<int>& owner, int part) {
  const std::vector<std::uint8_t> core = core_of(owner, part);
  ckpd::BodyRestriction r = ckpd::restrict_body(body, ckpd::core_and_halo(body, core));
  r.body.owned_centres.resize(r.global.size());
  for (std::size_t k = 0; k < r.global.size(); ++k) r.body.owned_centres[k] = core[r.global[k]];
  return r;
}

}  // namespace

TEST_CASE("restricted parts give the whole body's forces and energies", "[sub_body]") {
  ThreadCountGuard guard;
  const std::vector<Scene> scenes = {
      {"3D lattice nu=0.3", 3, 0.3, 0.0, 8, 6, 5},
      {"3D jittered cloud nu=0.3", 3, 0.3, 0.25, 7, 6, 5},
      {"2D lattice nu=0.4", 2, 0.4, 0.0, 16, 12, 1},
      {"2D jittered cloud nu=0.4", 2, 0.4, 0.25, 14, 12, 1},
      {"3D bonds only nu=0.25", 3, 0.25, 0.0, 8, 6, 5},
  };
  std::vector<Variant> variants;
  for (const ForceForm form : {ForceForm::own_family, ForceForm::energy_consistent})
    for (const bool stencil : {true, false})
      for (const DamageRule rule : {DamageRule::centre_bonds, DamageRule::all_edges})
        variants.push_back({form, rule, stencil});
  for (const Scene& s : scenes)
    for (const Variant& v : variants) {
      if (v.stencil && s.jitter > 0) continue;
      // Bonds only: no sets, so neither the stencil nor the force forms differ.
      if (s.nu == 0.25 && (v.stencil || v.form == ForceForm::energy_consistent)) continue;
      std::mt19937 rng(2718);
      Body body = make(s, v, rng);
      for (const bool random : {false, true}) {
        const int parts = random ? 3 : 2;
        const std::vector<int> owner = owners(body, parts, random, rng);
        const std::string label =
            s.label + ", " + ckpd::to_string(v.rule) + ", " + ckpd::to_string(v.form) +
            (v.stencil ? ", stencil" : ", general") + (random ? ", random owners" : ", slabs");
        // The whole body's kernel at one thread, per part (owned_centres) and whole.
        omp_set_num_threads(1);
        std::vector<std::vector<Vec3>> part_force(parts);
        std::vector<std::vector<double>> part_energy(parts);
        for (int p = 0; p < parts; ++p) {
          body.owned_centres = core_of(owner, p);
          ckpd::compute_internal_force_symmetric(body, true);
          part_force[static_cast<std::size_t>(p)] = body.force_density;
          part_energy[static_cast<std::size_t>(p)] = body.strain_energy_density;
        }
        body.owned_centres.clear();
        ckpd::compute_internal_force_symmetric(body, true);
        const std::vector<Vec3> force = body.force_density;
        const std::vector<double> energy = body.strain_energy_density;
        const double fscale = max_norm(force), escale = max_abs(energy);
        REQUIRE(fscale > 0);
        for (const int threads : {1, 2}) {
          omp_set_num_threads(threads);
          std::vector<Vec3> sum_force(body.size(), Vec3::Zero());
          std::vector<double> sum_energy(body.size(), 0.0);
          std::size_t mismatched = 0;
          for (int p = 0; p < parts; ++p) {
            ckpd::BodyRestriction r = part_restriction(body, owner, p);
            for (auto& f : r.body.force_density) f = Vec3::Constant(1e300);  // overwritten
            ckpd::compute_internal_force_symmetric(r.body, true);
            for (std::size_t k = 0; k < r.global.size(); ++k) {
              const std::size_t g = r.global[k];
              sum_force[g] += r.body.force_density[k];
              sum_energy[g] += r.body.strain_energy_density[k];
              const std::size_t pp = static_cast<std::size_t>(p);
              if (threads == 1 && (r.body.force_density[k] != part_force[pp][g] ||
                                   r.body.strain_energy_density[k] != part_energy[pp][g]))
                ++mismatched;
            }
          }
          double df = 0, de = 0;
          for (std::size_t i = 0; i < body.size(); ++i) {
            df = std::max(df, (sum_force[i] - force[i]).norm());
            de = std::max(de, std::abs(sum_energy[i] - energy[i]));
          }
          INFO(label << ", " << threads << " thread(s): force " << df / fscale << ", energy "
                     << de / escale << ", points differing from the body's partial forces "
                     << mismatched);
          CHECK(df <= 1e-12 * fscale);
          CHECK(de <= 1e-12 * escale);
          CHECK(mismatched == 0);
        }
      }
    }
}

TEST_CASE("a core's halo is its family members and the restriction keeps their bonds",
          "[sub_body]") {
  std::mt19937 rng(99);
  const Scene s{"3D lattice nu=0.3", 3, 0.3, 0.0, 8, 6, 5};
  Body body = make(s, {ForceForm::own_family, DamageRule::centre_bonds, true}, rng);
  const std::vector<int> owner = owners(body, 2, false, rng);
  const std::vector<std::uint8_t> core = core_of(owner, 0);
  const std::vector<std::uint32_t> kept = ckpd::core_and_halo(body, core);
  std::vector<std::uint8_t> is_kept(body.size(), 0);
  for (const std::uint32_t p : kept) is_kept[p] = 1;
  const auto& f = body.family;
  for (std::size_t i = 0; i < body.size(); ++i) {
    bool near_core = core[i] != 0;
    for (std::size_t k = f.offset[i]; k < f.offset[i + 1]; ++k) near_core |= core[f.neighbour[k]];
    CHECK(bool(is_kept[i]) == near_core);
  }
  const ckpd::BodyRestriction r = ckpd::restrict_body(body, kept);
  REQUIRE(r.body.size() == kept.size());
  std::size_t bonds = 0;
  for (std::size_t k = 0; k < kept.size(); ++k) {
    const std::size_t i = kept[k];
    std::size_t expected = 0;
    for (std::size_t e = f.offset[i]; e < f.offset[i + 1]; ++e) {
      if (!is_kept[f.neighbour[e]]) continue;
      const std::size_t local = r.body.family.offset[k] + expected++;
      CHECK(r.global[r.body.family.neighbour[local]] == f.neighbour[e]);
      CHECK(r.body.bond_intact[local] == body.bond_intact[e]);
    }
    CHECK(r.body.family.family_size(k) == expected);
    // A core point keeps its whole family.
    if (core[i] != 0) CHECK(expected == f.family_size(i));
    bonds += expected;
  }
  CHECK(r.body.family.bond_entries() == bonds);
  CHECK(r.body.bond_intact.size() == bonds);
}

TEST_CASE("bond failure on a restriction breaks the bonds the whole body breaks", "[sub_body]") {
  // Both stored directions of a bond compute the same stretch from the same positions, so a bond
  // two parts hold is decided alike by both.
  std::mt19937 rng(5);
  const Scene s{"3D lattice nu=0.3", 3, 0.3, 0.0, 8, 6, 5};
  Body body = make(s, {ForceForm::own_family, DamageRule::all_edges, true}, rng);
  body.critical_stretch = 0.02;
  perturb(body, 0.03, rng);  // stretches up to about 0.06: a share of the bonds fail
  const std::vector<int> owner = owners(body, 2, false, rng);
  std::vector<ckpd::BodyRestriction> parts;
  for (int p = 0; p < 2; ++p) parts.push_back(part_restriction(body, owner, p));
  const std::size_t failed = ckpd::update_bond_failure(body);
  REQUIRE(failed > 0);
  for (ckpd::BodyRestriction& r : parts) {
    ckpd::update_bond_failure(r.body);
    CHECK(differing_flags(body, r, false) == 0);
  }
}

TEST_CASE("restrictions booking their own points add up to the whole body's books", "[sub_body]") {
  // Body::booked_points: each part books the strain energy, the energy its failing bonds take
  // and the failed bonds (at their lower ends) of its own points only, so the parts' figures sum
  // to the whole body's: both damage rules, sets and bonds only, 1 and 2 threads.
  ThreadCountGuard guard;
  for (const DamageRule rule : {DamageRule::all_edges, DamageRule::centre_bonds})
    for (const double nu : {0.3, 0.25})
      for (const int threads : {1, 2}) {
        INFO("rule " << static_cast<int>(rule) << ", nu " << nu << ", threads " << threads);
        omp_set_num_threads(threads);
        std::mt19937 rng(9);
        const Scene s{"3D lattice", 3, nu, 0.0, 8, 6, 5};
        // nu = 1/4: bonds only (no stencil tables to build)
        Body body = make(s, {ForceForm::own_family, rule, nu != 0.25}, rng);
        overstretch(body, rng);
        const std::vector<int> owner = owners(body, 3, true, rng);
        std::vector<ckpd::BodyRestriction> parts;
        for (int p = 0; p < 3; ++p) {
          parts.push_back(part_restriction(body, owner, p));
          ckpd::BodyRestriction& r = parts.back();
          r.body.booked_points.assign(r.global.size(), 0);
          for (std::size_t k = 0; k < r.global.size(); ++k)
            r.body.booked_points[k] = owner[r.global[k]] == p;
        }
        const double half_drift = 1e-2;
        const ckpd::FailureUpdate whole = ckpd::fail_overstretched_bonds(body, half_drift);
        REQUIRE(whole.failed > 0);
        ckpd::compute_internal_force_symmetric(body, true);
        double dissipated = 0, strain = 0;
        std::size_t failed = 0, counted = 0;
        for (ckpd::BodyRestriction& r : parts) {
          const ckpd::FailureUpdate mine = ckpd::fail_overstretched_bonds(r.body, half_drift);
          failed += mine.failed;
          dissipated += mine.dissipated;
          counted += ckpd::failed_bond_count(r.body);
          // The booked points' energy densities are their whole families' (a restriction keeps a
          // booked point's family whole).
          r.body.owned_centres.clear();
          ckpd::compute_internal_force_symmetric(r.body, true);
          strain += ckpd::strain_energy(r.body);
        }
        CHECK(failed == whole.failed);
        CHECK(counted == ckpd::failed_bond_count(body));
        CHECK(std::abs(dissipated - whole.dissipated) <= 1e-12 * std::abs(whole.dissipated));
        const double total = ckpd::strain_energy(body);
        CHECK(std::abs(strain - total) <= 1e-12 * total);
      }
}

TEST_CASE("the fused bond-only kernel on restrictions fails, books and forces as on the whole body",
          "[sub_body]") {
  // A rank's restriction (owned_centres = booked_points = its points) of a bond-only body takes the
  // fused kernel (symmetric/bond_only.hpp): its owned points' bonds fail inside the force pass,
  // and the bonds from ghosts below them by ghost_bond_failures. The parts' flags of their points'
  // families, failed counts, dissipated energy and partial forces must be the whole body's.
  ThreadCountGuard guard;
  for (const DamageRule rule : {DamageRule::all_edges, DamageRule::centre_bonds})
    for (const int threads : {1, 2}) {
      INFO("rule " << static_cast<int>(rule) << ", threads " << threads);
      omp_set_num_threads(threads);
      std::mt19937 rng(11);
      const Scene s{"3D lattice, bonds only", 3, 0.25, 0.0, 8, 6, 5};
      Body body = make(s, {ForceForm::own_family, rule, false}, rng);
      const std::size_t before = overstretch(body, rng);
      const std::vector<int> owner = owners(body, 3, true, rng);
      std::vector<ckpd::BodyRestriction> parts;
      for (int p = 0; p < 3; ++p) {
        parts.push_back(part_restriction(body, owner, p));
        parts.back().body.booked_points = parts.back().body.owned_centres;
      }
      const double half_drift = 1e-2;
      ckpd::FailureUpdate whole;
      ckpd::fail_bonds_and_compute_internal_force(body, true, half_drift, whole);
      REQUIRE(whole.failed > 0);
      REQUIRE(ckpd::failed_bond_count(body) == before + whole.failed);
      std::vector<Vec3> force(body.size(), Vec3::Zero());
      double dissipated = 0, largest = 0;
      std::size_t failed = 0, differing = 0;
      for (ckpd::BodyRestriction& r : parts) {
        ckpd::FailureUpdate mine;
        ckpd::fail_bonds_and_compute_internal_force(r.body, true, half_drift, mine);
        failed += mine.failed;
        dissipated += mine.dissipated;
        for (std::size_t k = 0; k < r.global.size(); ++k)
          force[r.global[k]] += r.body.force_density[k];
        differing += differing_flags(body, r, true);
      }
      CHECK(differing == 0);
      CHECK(failed == whole.failed);
      CHECK(std::abs(dissipated - whole.dissipated) <= 1e-12 * std::abs(whole.dissipated));
      for (const Vec3& f : body.force_density) largest = std::max(largest, f.norm());
      double worst = 0;
      for (std::size_t i = 0; i < body.size(); ++i)
        worst = std::max(worst, (force[i] - body.force_density[i]).norm());
      CHECK(worst <= 1e-12 * largest);
    }
}

TEST_CASE("restrict_body rejects points out of order or range", "[sub_body]") {
  std::mt19937 rng(1);
  const Scene s{"2D lattice", 2, 0.4, 0.0, 6, 6, 1};
  const Body body = make(s, {ForceForm::own_family, DamageRule::centre_bonds, false}, rng);
  CHECK_THROWS_AS(ckpd::restrict_body(body, {3, 2}), std::invalid_argument);
  CHECK_THROWS_AS(ckpd::restrict_body(body, {1, 1}), std::invalid_argument);
  CHECK_THROWS_AS(ckpd::restrict_body(body, {0, 36}), std::invalid_argument);
  CHECK_THROWS_AS(ckpd::core_and_halo(body, std::vector<std::uint8_t>(5, 1)),
                  std::invalid_argument);
}
