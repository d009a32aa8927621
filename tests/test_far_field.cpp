// The adaptive far field (bodies/far_field.hpp): the classification follows its definition
// (checked point by point against a direct evaluation of it), exact points get the reference
// kernel's exact force, linear points the linear operator's row and the quadratic energy; with
// every point exact the force is the symmetric kernel's bit for bit, with every point linear the
// linear operator's bit for bit; exact stays exact. 2D and 3D, lattice (stencil path) and
// jittered cloud, both force forms, random failed bonds, 1 and 2 threads.
#include <omp.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "bodies/body.hpp"
#include "bodies/far_field.hpp"
#include "bodies/linear_operator.hpp"
#include "kernel_comparison.hpp"
#include "reference/internal_force.hpp"

using ckpd::Body;
using ckpd::ForceForm;
using ckpd::Vec3;

namespace {

struct FarScene {
  kernel_comparison::Scene scene;
  ForceForm form;
};

const std::vector<FarScene>& scenes() {
  static const std::vector<FarScene> all = [] {
    std::vector<FarScene> v;
    const std::vector<kernel_comparison::Scene> geometry = {
        {"2D lattice, nu=0.4", 2, 0.4, 0.0, 12, 10, 1},
        {"2D jittered cloud, nu=0.3", 2, 0.3, 0.2, 12, 10, 1},
        {"3D lattice, nu=0.3", 3, 0.3, 0.0, 12, 6, 6},
        {"3D jittered cloud", 3, 0.3, 0.2, 12, 6, 6},
    };
    for (const auto& g : geometry)
      for (ForceForm f : {ForceForm::own_family, ForceForm::energy_consistent}) v.push_back({g, f});
    return v;
  }();
  return all;
}

std::string label(const FarScene& fs) {
  return fs.scene.label + ", " + ckpd::to_string(fs.form);
}

// A body with failed bonds is a damaged one: damage_enabled makes the kernels and the
// classification read the bonds' flags.
void fail_bonds_in_first_quarter(Body& body, double fraction, std::mt19937& rng) {
  body.damage_enabled = true;
  kernel_comparison::fail_bonds(body, fraction, rng);
  const std::size_t quarter = body.size() / 4;
  for (std::size_t i = 0; i < body.size(); ++i)
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k)
      if (i >= quarter || body.family.neighbour[k] >= quarter) body.bond_intact[k] = 1;
}

// The force form is set in the definition: make_body picks the symmetric kernel's table by it.
// Failed bonds (with probability failed_fraction) only among the first quarter of the points,
// where mixed_displacement strains too: the rest of the body stays linear.
Body scene_body(const FarScene& fs, double failed_fraction, std::mt19937& rng) {
  using namespace kernel_comparison;
  const Scene& s = fs.scene;
  ckpd::BodyDefinition d =
      block(s.dimension, s.nx, s.ny, s.nz, constants_for(s), s.jitter, rng, s.m);
  d.force_form = fs.form;
  Body body = ckpd::make_body(std::move(d));
  if (failed_fraction > 0) fail_bonds_in_first_quarter(body, failed_fraction, rng);
  return body;
}

// The definition, evaluated directly over all pairs of {i} and i's family: some bond between
// two of them has failed, or some bond of i changes its vector by T L or more.
std::vector<std::uint8_t> expected_exact(const Body& body, double T) {
  const auto& f = body.family;
  auto failed_bond = [&](std::uint32_t p, std::uint32_t q) {
    for (std::size_t k = f.offset[p]; k < f.offset[p + 1]; ++k)
      if (f.neighbour[k] == q) return !body.bond_intact[k];
    return false;  // not bonded
  };
  std::vector<std::uint8_t> exact(body.size(), 0);
  for (std::size_t i = 0; i < body.size(); ++i) {
    std::vector<std::uint32_t> points{static_cast<std::uint32_t>(i)};
    bool e = false;
    for (std::size_t k = f.offset[i]; k < f.offset[i + 1]; ++k) {
      const std::uint32_t j = f.neighbour[k];
      points.push_back(j);
      const double L = (body.reference_position[j] - body.reference_position[i]).norm();
      e = e || (body.displacement[j] - body.displacement[i]).norm() >= T * L;
    }
    for (std::size_t a = 0; a < points.size() && !e; ++a)
      for (std::size_t b = a + 1; b < points.size() && !e; ++b)
        e = failed_bond(points[a], points[b]);
    exact[i] = e;
  }
  return exact;
}

// Displacements small everywhere (1e-6 dx) and larger (1e-2 dx) in the body's first quarter
// of points: a mixed state at T = 1e-4.
void mixed_displacement(Body& body, std::mt19937& rng) {
  kernel_comparison::perturb(body, 1e-6, rng);
  std::uniform_real_distribution<double> u(-1e-2 * kernel_comparison::kDx,
                                           1e-2 * kernel_comparison::kDx);
  for (std::size_t i = 0; i < body.size() / 4; ++i)
    body.displacement[i] += Vec3(u(rng), u(rng), body.dimension == 3 ? u(rng) : 0.0);
}

}  // namespace

TEST_CASE(
    "far field: exact points get the reference kernel's force, linear points the "
    "linear operator's, classification as defined",
    "[far_field]") {
  kernel_comparison::ThreadCountGuard guard;
  for (const FarScene& fs : scenes()) {
    std::mt19937 rng(5);
    Body body = scene_body(fs, 0.002, rng);
    mixed_displacement(body, rng);
    const double T = 1e-4;
    ckpd::compute_internal_force(body, true);  // the reference kernel: every set, every point
    const std::vector<Vec3> exact_force = body.force_density;
    const double scale = kernel_comparison::max_norm(exact_force);
    std::vector<Vec3> linear_force;
    ckpd::FarField ff = ckpd::make_far_field(body, T);
    ckpd::apply_linear_operator(ff.op, body, linear_force);
    const std::vector<std::uint8_t> expected = expected_exact(body, T);
    for (int threads : {1, 2}) {
      omp_set_num_threads(threads);
      ckpd::FarField f = ckpd::make_far_field(body, T);
      for (auto& x : body.force_density) x = Vec3::Constant(1e300);
      ckpd::compute_internal_force_far_field(body, f, true);
      INFO(label(fs) << ", " << threads << " threads");
      std::size_t exact = 0, mismatched = 0;
      double worst_exact = 0;
      bool linear_equal = true, energy_equal = true;
      for (std::size_t i = 0; i < body.size(); ++i) {
        mismatched += f.exact[i] != expected[i];
        if (f.exact[i]) {
          ++exact;
          worst_exact = std::max(worst_exact, (body.force_density[i] - exact_force[i]).norm());
        } else {
          linear_equal = linear_equal && body.force_density[i] == linear_force[i];
          energy_equal = energy_equal && body.strain_energy_density[i] ==
                                             ckpd::linear_energy_density(ff.op, body, i);
        }
      }
      CHECK(mismatched == 0);
      CHECK(f.exact_count == exact);
      CHECK(exact > 0);  // the state is mixed
      CHECK(exact < body.size());
      CHECK(worst_exact <= 1e-12 * scale);
      CHECK(linear_equal);
      CHECK(energy_equal);
    }
  }
}

// A uniform stretch along x at a multiple g / T of the tolerance: |u^j - u^i| / L^ij = g |n_x| for
// every bond, so the screen is g wherever a bond runs along x, while the largest |u^j - u^i| over
// a family is the horizon's g (m dx) against the shortest bond's dx. The classification's bound
// through the shortest bond cannot decide such a point (its |u^j - u^i|^2 / L_min^2 is m^2 g^2):
// every point takes the bond-by-bond screen, and the decision is the definition's on either
// side of the tolerance.
TEST_CASE("far field: points the shortest-bond bound cannot decide get the bond-by-bond screen",
          "[far_field]") {
  kernel_comparison::ThreadCountGuard guard;
  for (const FarScene& fs : scenes()) {
    if (fs.form != ForceForm::energy_consistent) continue;  // the screen does not read the form
    std::mt19937 rng(13);
    Body body = scene_body(fs, 0.0, rng);
    const double T = 1e-4;
    for (double ratio : {0.97, 1.03}) {
      for (std::size_t i = 0; i < body.size(); ++i)
        body.displacement[i] = Vec3(ratio * T * body.reference_position[i].x(), 0, 0);
      const std::vector<std::uint8_t> expected = expected_exact(body, T);
      for (int threads : {1, 2}) {
        omp_set_num_threads(threads);
        INFO(label(fs) << ", g = " << ratio << " T, " << threads << " threads");
        ckpd::FarField f = ckpd::make_far_field(body, T);
        ckpd::classify_far_field(body, f);
        std::size_t mismatched = 0, exact = 0;
        for (std::size_t i = 0; i < body.size(); ++i) {
          mismatched += f.exact[i] != expected[i];
          exact += f.exact[i];
        }
        CHECK(mismatched == 0);
        if (ratio < 1) {
          CHECK(exact == 0);
        } else {
          CHECK(exact > body.size() / 2);  // the bonds within 14 degrees of x reach T
        }
      }
    }
  }
}

TEST_CASE(
    "far field with every point exact is the symmetric kernel bit for bit; with every "
    "point linear the linear operator bit for bit",
    "[far_field]") {
  kernel_comparison::ThreadCountGuard guard;
  for (const FarScene& fs : scenes()) {
    std::mt19937 rng(8);
    Body body = scene_body(fs, 0.0, rng);
    kernel_comparison::perturb(body, 1e-8, rng);
    for (int threads : {1, 2}) {
      omp_set_num_threads(threads);
      INFO(label(fs) << ", " << threads << " threads");
      ckpd::compute_internal_force_symmetric(body, true);
      const std::vector<Vec3> kernel = body.force_density;
      const std::vector<double> kernel_energy = body.strain_energy_density;
      ckpd::FarField tiny = ckpd::make_far_field(body, 1e-300);
      ckpd::compute_internal_force_far_field(body, tiny, true);
      CHECK(tiny.exact_count == body.size());
      CHECK(body.force_density == kernel);
      CHECK(body.strain_energy_density == kernel_energy);

      ckpd::FarField huge = ckpd::make_far_field(body, 1e300);
      std::vector<Vec3> linear;
      ckpd::apply_linear_operator(huge.op, body, linear);
      ckpd::compute_internal_force_far_field(body, huge, true);
      CHECK(huge.exact_count == 0);
      CHECK(body.force_density == linear);
      // The linear force is the exact one to first order: at strain 1e-8, within 1e-3 of it.
      double worst = 0;
      for (std::size_t i = 0; i < body.size(); ++i)
        worst = std::max(worst, (linear[i] - kernel[i]).norm());
      CHECK(worst <= 1e-3 * kernel_comparison::max_norm(kernel));
      // Quadratic energy: the exact energy to first order in the strain, where the forces are
      // its gradient (energy_consistent; own_family's forces are not).
      if (fs.form != ForceForm::energy_consistent) continue;
      double e_lin = 0, e_exact = 0;
      for (std::size_t i = 0; i < body.size(); ++i) {
        e_lin += body.volume[i] * body.strain_energy_density[i];
        e_exact += body.volume[i] * kernel_energy[i];
      }
      CHECK(std::abs(e_lin - e_exact) <= 1e-3 * std::abs(e_exact));
    }
  }
}

TEST_CASE(
    "far field: bonds failing after the operator's assembly leave the linear points' forces "
    "the exact ones to first order, next to the damage too",
    "[far_field]") {
  // The classification keeps a point linear when the failed bonds near it have an end outside
  // its family; its operator row, assembled with every bond intact, must then still be the
  // exact force's linearisation. At strain 1e-8 the linear force is within 1e-5 of the exact
  // one; a row that missed a switched-off set would be off by the set's share, orders more.
  kernel_comparison::ThreadCountGuard guard;
  for (const FarScene& fs : scenes()) {
    std::mt19937 rng(21);
    Body body = scene_body(fs, 0.0, rng);
    kernel_comparison::perturb(body, 1e-8, rng);
    ckpd::FarField ff = ckpd::make_far_field(body, 1e300);  // every bond intact here
    Body damaged = body;
    fail_bonds_in_first_quarter(damaged, 0.01, rng);
    ckpd::compute_internal_force(damaged, false);  // the reference kernel
    const std::vector<Vec3> exact_force = damaged.force_density;
    const double scale = kernel_comparison::max_norm(exact_force);
    const std::vector<std::uint8_t> expected = expected_exact(damaged, 1e300);
    for (int threads : {1, 2}) {
      omp_set_num_threads(threads);
      INFO(label(fs) << ", " << threads << " threads");
      ckpd::FarField f = ff;
      ckpd::compute_internal_force_far_field(damaged, f, false);
      std::size_t linear_near_damage = 0, mismatched = 0;
      double worst = 0;
      for (std::size_t i = 0; i < damaged.size(); ++i) {
        mismatched += f.exact[i] != expected[i];
        worst = std::max(worst, (damaged.force_density[i] - exact_force[i]).norm());
        if (f.exact[i]) continue;
        bool near = false;  // a member with a failed bond (the former rule made i exact)
        const auto& fam = damaged.family;
        for (std::size_t k = fam.offset[i]; k < fam.offset[i + 1] && !near; ++k) {
          const std::uint32_t j = fam.neighbour[k];
          for (std::size_t q = fam.offset[j]; q < fam.offset[j + 1] && !near; ++q)
            near = !damaged.bond_intact[q];
        }
        linear_near_damage += near;
      }
      CHECK(mismatched == 0);
      CHECK(f.exact_count > 0);
      CHECK(linear_near_damage > 0);  // the case the rule is about occurs
      CHECK(worst <= 1e-5 * scale);
    }
  }
}

TEST_CASE(
    "far field: bonds failing over several classifications make exact the points a "
    "classification from scratch makes exact",
    "[far_field]") {
  // The classification marks the neighbourhood of a failed bond when it first sees the bond
  // failed; each round below fails more bonds across the whole body (none at the set-up) and
  // compares with the rule applied from scratch. At strain 1e-8 no point is exact by strain.
  kernel_comparison::ThreadCountGuard guard;
  for (const FarScene& fs : scenes()) {
    for (int threads : {1, 2}) {
      omp_set_num_threads(threads);
      std::mt19937 rng(31);
      Body body = scene_body(fs, 0.0, rng);
      body.damage_enabled = true;
      kernel_comparison::perturb(body, 1e-8, rng);
      ckpd::FarField ff = ckpd::make_far_field(body, 1e-3);
      std::size_t previous = 0;
      for (int round = 0; round < 3; ++round) {
        INFO(label(fs) << ", " << threads << " threads, round " << round);
        if (round > 0) kernel_comparison::fail_bonds(body, 0.0005, rng);
        ckpd::classify_far_field(body, ff);
        const std::vector<std::uint8_t> expected = expected_exact(body, 1e-3);
        std::size_t mismatched = 0;
        for (std::size_t i = 0; i < body.size(); ++i) mismatched += ff.exact[i] != expected[i];
        CHECK(mismatched == 0);
        if (round == 0) CHECK(ff.exact_count == 0);
        if (round > 0) CHECK(ff.exact_count > previous);  // the new failures' neighbourhoods
        CHECK(ff.exact_count < body.size());
        previous = ff.exact_count;
      }
    }
  }
}

TEST_CASE("far field: a point once exact stays exact when its strain falls back", "[far_field]") {
  const FarScene fs = scenes()[2];
  std::mt19937 rng(3);
  Body body = scene_body(fs, 0.0, rng);
  mixed_displacement(body, rng);
  ckpd::FarField ff = ckpd::make_far_field(body, 1e-4);
  ckpd::classify_far_field(body, ff);
  const std::vector<std::uint8_t> before = ff.exact;
  REQUIRE(ff.exact_count > 0);
  for (Vec3& u : body.displacement) u.setZero();
  ckpd::classify_far_field(body, ff);
  CHECK(ff.exact == before);
}

TEST_CASE(
    "far field per-set masking leaves the exact points' forces and energies bit for bit as "
    "evaluating every set, and evaluates fewer sets",
    "[far_field]") {
  kernel_comparison::ThreadCountGuard guard;
  for (const FarScene& fs : scenes()) {
    std::mt19937 rng(13);
    Body body = scene_body(fs, 0.0, rng);
    // A strained band with failed bonds across the middle of the body in x (the slowest index
    // is not x), so that linear centres have exact upper neighbours (the masking's case).
    double x0 = 1e300, x1 = -1e300;
    for (const Vec3& X : body.reference_position)
      x0 = std::min(x0, X.x()), x1 = std::max(x1, X.x());
    std::vector<std::uint8_t> band(body.size());
    for (std::size_t i = 0; i < body.size(); ++i) {
      const double x = (body.reference_position[i].x() - x0) / (x1 - x0);
      band[i] = x > 0.4 && x < 0.6;
    }
    kernel_comparison::fail_bonds(body, 0.002, rng);
    for (std::size_t i = 0; i < body.size(); ++i)
      for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k)
        if (!band[i] || !band[body.family.neighbour[k]]) body.bond_intact[k] = 1;
    kernel_comparison::perturb(body, 1e-6, rng);
    std::uniform_real_distribution<double> u(-1e-2 * kernel_comparison::kDx,
                                             1e-2 * kernel_comparison::kDx);
    for (std::size_t i = 0; i < body.size(); ++i)
      if (band[i]) body.displacement[i] += Vec3(u(rng), u(rng), body.dimension == 3 ? u(rng) : 0.0);
    for (int threads : {1, 2}) {
      omp_set_num_threads(threads);
      for (bool energy : {false, true}) {
        INFO(label(fs) << ", " << threads << " threads, energy " << energy);
        ckpd::FarField all = ckpd::make_far_field(body, 1e-4);
        all.mask_sets = false;
        const ckpd::SymmetricKernelStats every =
            ckpd::compute_internal_force_far_field(body, all, energy);
        const std::vector<Vec3> force = body.force_density;
        const std::vector<double> density = body.strain_energy_density;
        ckpd::FarField masked = ckpd::make_far_field(body, 1e-4);
        for (auto& x : body.force_density) x = Vec3::Constant(1e300);
        const ckpd::SymmetricKernelStats fewer =
            ckpd::compute_internal_force_far_field(body, masked, energy);
        REQUIRE(masked.exact == all.exact);
        REQUIRE(masked.exact_count > 0);
        REQUIRE(masked.exact_count < body.size());
        bool forces_equal = true, energies_equal = true;
        for (std::size_t i = 0; i < body.size(); ++i) {
          forces_equal = forces_equal && body.force_density[i] == force[i];
          if (energy)
            energies_equal = energies_equal && body.strain_energy_density[i] == density[i];
        }
        CHECK(forces_equal);  // exact rows from the kernel, linear rows from the operator
        CHECK(energies_equal);
        CHECK(fewer.bonds < every.bonds);
        CHECK(fewer.bonds + fewer.triangles + fewer.tetrahedra <
              every.bonds + every.triangles + every.tetrahedra);
        if (body.dimension == 3) CHECK(fewer.tetrahedra < every.tetrahedra);
      }
    }
  }
}
