// The nonlinear ordinary state-based solid (bodies/state_based_model.hpp) against an independent
// reference: its energy written out from the formula (state_based_reference.hpp), central finite
// differences of that energy (forces = -grad E for m = 1/2, 0, -1/2, 2D and 3D, random damage),
// the continuum moduli (its own patch test), the failure criterion, the free-surface parameter
// and the stiffness bound (the largest eigenvalue of the tangent, by power iteration).
#include <omp.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <iostream>
#include <random>

#include "bodies/damage.hpp"
#include "bodies/point_kernel.hpp"
#include "bodies/state_based_model.hpp"
#include "bodies/symmetric_kernel.hpp"
#include "body_fixtures.hpp"
#include "state_based_reference.hpp"

using ckpd::Body;
using ckpd::Vec3;

namespace {

Body state_based_block(int dimension, int n, double m, double lambda_bar = 3e9, double mu_bar = 2e9,
                       double fracture_energy = 0) {
  ckpd::BodyDefinition d = ckpd_test::lattice_block(dimension, n, n, dimension == 3 ? n : 1, 1e-3,
                                                    3.015, {0, 0, 0}, 1000.0);
  d.model = &ckpd::state_based_kernels();
  d.state_based.lambda_bar = lambda_bar;
  d.state_based.mu_bar = mu_bar;
  d.state_based.m = m;
  if (fracture_energy > 0)
    d.state_based.failure_beta =
        ckpd::state_based_failure_beta(dimension, d.horizon, fracture_energy);
  return ckpd::make_body(std::move(d));
}

// The centre point of an n x n (x n) block.
std::size_t centre_point(const Body& b, int n) {
  const int c = n / 2;
  return b.dimension == 3 ? static_cast<std::size_t>((c * n + c) * n + c)
                          : static_cast<std::size_t>(c * n + c);
}

}  // namespace

TEST_CASE(
    "state-based solid: the kernel energy is the reference energy and its forces are "
    "minus the energy gradient",
    "[state_based]") {
  std::mt19937 rng(7);
  for (int dim : {2, 3}) {
    for (double m : {0.5, 0.0, -0.5}) {
      const int n = dim == 3 ? 6 : 9;
      Body b = state_based_block(dim, n, m);
      ckpd_test::fail_random_bonds(b, 0.15, rng);
      b.damage_enabled = true;
      ckpd_test::perturb(b, 5e-5, rng);  // strains of a few per cent, both signs
      ckpd::compute_internal_force_symmetric(b, true);
      const double e_kernel = ckpd::strain_energy(b);
      const double e_ref = state_based_reference::energy(b);
      INFO("dim " << dim << ", m = " << m);
      REQUIRE(e_ref > 0);
      CHECK(e_kernel == Approx(e_ref).epsilon(1e-12));
      const std::vector<Vec3> f = b.force_density;
      // Central differences of the reference energy at a few points (corner, edge, centre).
      const double h = 1e-8;
      double worst = 0, scale = 0;
      for (std::size_t p : {std::size_t{0}, std::size_t{3}, centre_point(b, n)}) {
        for (int c = 0; c < dim; ++c) {
          const double keep = b.displacement[p][c];
          b.displacement[p][c] = keep + h;
          const double ep = state_based_reference::energy(b);
          b.displacement[p][c] = keep - h;
          const double em = state_based_reference::energy(b);
          b.displacement[p][c] = keep;
          const double fd = -(ep - em) / (2 * h) / b.volume[p];
          worst = std::max(worst, std::abs(fd - f[p][c]));
          scale = std::max(scale, std::abs(f[p][c]));
        }
      }
      INFO("largest |force| " << scale << ", largest difference " << worst);
      REQUIRE(scale > 0);
      CHECK(worst < 1e-6 * scale);
      // The point entry (one point's own family, used for booking) gives the same force.
      ckpd::FamilyScratch scratch;
      for (std::size_t p = 0; p < b.size(); p += 7) {
        const ckpd::PointResult r = ckpd::evaluate_point(b, p, scratch);
        CHECK((r.force_density - f[p]).norm() <= 1e-12 * scale);
        CHECK(r.strain_energy_density() ==
              Approx(b.strain_energy_density[p]).epsilon(1e-12).margin(1e-300));
      }
    }
  }
}

TEST_CASE("state-based solid: 1 and 2 threads give the same forces and failures bit for bit",
          "[state_based]") {
  std::mt19937 rng(3);
  Body b = state_based_block(3, 7, 0.0, 3e9, 2e9, 10.0);
  ckpd_test::fail_random_bonds(b, 0.1, rng);
  ckpd_test::perturb(b, 4e-5, rng);
  const int threads = omp_get_max_threads();
  Body b2 = b;
  omp_set_num_threads(1);
  ckpd::compute_internal_force_symmetric(b, true);
  const ckpd::FailureUpdate u1 = ckpd::fail_overstretched_bonds(b, 0.0);
  omp_set_num_threads(2);
  ckpd::compute_internal_force_symmetric(b2, true);
  const ckpd::FailureUpdate u2 = ckpd::fail_overstretched_bonds(b2, 0.0);
  omp_set_num_threads(threads);
  CHECK(b2.force_density == b.force_density);
  CHECK(b2.strain_energy_density == b.strain_energy_density);
  CHECK(u1.failed > 0);
  CHECK(u1.failed == u2.failed);
  CHECK(u1.dissipated == u2.dissipated);
  CHECK(b.bond_intact == b2.bond_intact);
}

TEST_CASE("state-based solid: patch test, bulk and shear response against the continuum",
          "[state_based][patch]") {
  // Uniform strain E on a lattice block; the centre point's energy density against the
  // continuum's lambda (tr E)^2 / 2 + mu E:E with lambda = lambda_bar + mu, mu = mu_bar / 2
  // (2D) or 2 mu_bar / 5 (3D). Bulk (E = e I) is exact by the weight's normalisation; shear
  // (E = g (e1 e2 + e2 e1) / 2) is off by the discrete fourth moment of the family,
  // 2 mu_bar / mu * sum_j w V (n_x n_y)^2, which is computed here independently.
  for (int dim : {2, 3}) {
    const int n = dim == 3 ? 9 : 13;
    for (double m : {0.5, 0.0, -0.5}) {
      Body b = state_based_block(dim, n, m);
      const double mu = dim == 2 ? b.state_based.mu_bar / 2 : 0.4 * b.state_based.mu_bar;
      const double lambda = b.state_based.lambda_bar + mu;
      const std::size_t c = centre_point(b, n);
      const double strain = 1e-6;
      auto density_at = [&](const Eigen::Matrix3d& E) {
        for (std::size_t i = 0; i < b.size(); ++i) b.displacement[i] = E * b.reference_position[i];
        ckpd::compute_internal_force_symmetric(b, true);
        return b.strain_energy_density[c];
      };
      Eigen::Matrix3d bulk = Eigen::Matrix3d::Zero();
      for (int k = 0; k < dim; ++k) bulk(k, k) = strain;
      Eigen::Matrix3d shear = Eigen::Matrix3d::Zero();
      shear(0, 1) = shear(1, 0) = strain / 2;
      const double bulk_continuum =
          0.5 * lambda * dim * dim * strain * strain + mu * dim * strain * strain;
      const double shear_continuum = mu * strain * strain / 2;
      const double bulk_ratio = density_at(bulk) / bulk_continuum;
      const double shear_ratio = density_at(shear) / shear_continuum;
      // The family's discrete zeroth and fourth moments (normalised weight).
      double m4 = 0, m0 = 0;
      for (std::size_t k = b.family.offset[c]; k < b.family.offset[c + 1]; ++k) {
        const Vec3 xi = b.reference_position[b.family.neighbour[k]] - b.reference_position[c];
        const double w = b.state_based.weight_scale *
                         ckpd::state_based_weight(dim, xi.norm(), b.horizon) * b.volume[0];
        const Vec3 e = xi.normalized();
        m4 += w * e.x() * e.x() * e.y() * e.y();
        m0 += w;
      }
      const double expected_shear = 2 * b.state_based.mu_bar / mu * m4;
      std::cout << "state-based patch test " << dim << "D, m = " << m << ": bulk ratio "
                << bulk_ratio << ", shear ratio " << shear_ratio << " (discrete fourth moment "
                << expected_shear << ")\n";
      INFO(dim << "D m = " << m);
      CHECK(m0 == Approx(dim).epsilon(1e-12));  // tr_w(1) = d for the full family
      CHECK(bulk_ratio == Approx(1).epsilon(1e-5));
      CHECK(shear_ratio == Approx(expected_shear).epsilon(1e-5));
      // The discretisation's ratio at delta = 3.015 dx: 0.73 (2D), 0.82 (3D), printed above.
      CHECK(shear_ratio > 0.6);
      CHECK(shear_ratio < 1.0);
    }
  }
}

TEST_CASE("state-based solid: the shear ratio tends to 1 as the horizon holds more points",
          "[state_based][patch]") {
  // 2D, delta = 3.015, 4.015, 6.015 dx: the discrete fourth moment approaches the continuum's.
  double previous = 0;
  for (double ratio : {3.015, 4.015, 6.015}) {
    ckpd::BodyDefinition d = ckpd_test::lattice_block(2, 15, 15, 1, 1e-3, ratio, {0, 0, 0}, 1000.0);
    d.model = &ckpd::state_based_kernels();
    d.state_based.lambda_bar = 3e9;
    d.state_based.mu_bar = 2e9;
    Body b = ckpd::make_body(std::move(d));
    const std::size_t c = centre_point(b, 15);
    const double g = 1e-6;
    for (std::size_t i = 0; i < b.size(); ++i)
      b.displacement[i] =
          Vec3(0.5 * g * b.reference_position[i].y(), 0.5 * g * b.reference_position[i].x(), 0);
    ckpd::compute_internal_force_symmetric(b, true);
    const double shear_ratio = b.strain_energy_density[c] / (b.state_based.mu_bar / 2 * g * g / 2);
    std::cout << "state-based shear ratio, 2D, delta / dx = " << ratio << ": " << shear_ratio
              << '\n';
    CHECK(std::abs(1 - shear_ratio) < std::abs(1 - previous));
    previous = shear_ratio;
  }
  CHECK(previous == Approx(1).epsilon(0.1));
}

TEST_CASE("state-based solid: a bond fails when its instantaneous energy reaches beta over xi^2",
          "[state_based][damage]") {
  // 2D, uniform stretch e in x: the criterion's mean over both ends is checked bond by bond
  // against what failed, and the booked energy against the reference energy's drop.
  const double Gc = 5.0;
  Body b = state_based_block(2, 11, 0.5, 3e9, 2e9, Gc);
  REQUIRE(b.damage_enabled);
  const double beta = ckpd::state_based_failure_beta(2, b.horizon, Gc);
  CHECK(beta == Approx(M_PI * b.horizon * Gc / 16));
  const double e = 5e-4;  // long bonds fail, short ones do not
  for (std::size_t i = 0; i < b.size(); ++i)
    b.displacement[i] = Vec3(e * b.reference_position[i].x(), 0, 0);
  std::vector<double> theta;
  ckpd::state_based_dilatation(b, theta);
  std::size_t expected = 0;
  std::vector<std::uint8_t> should(b.bond_intact.size(), 0);
  for (std::size_t i = 0; i < b.size(); ++i)
    for (std::size_t k = b.family.offset[i]; k < b.family.offset[i + 1]; ++k) {
      const std::size_t j = b.family.neighbour[k];
      const Vec3 xi = b.reference_position[j] - b.reference_position[i];
      const Vec3 Y = xi + b.displacement[j] - b.displacement[i];
      const double eps = Y.norm() / xi.norm() - 1;
      const double s = 0.5 * b.state_based.lambda_bar * eps * (theta[i] + theta[j]) +
                       b.state_based.mu_bar * eps * eps;
      if (eps >= 0 && s >= beta / xi.squaredNorm()) {
        should[k] = 1;
        if (i < j) ++expected;
      }
    }
  REQUIRE(expected > 0);
  REQUIRE(expected < b.bond_count() / 2);  // the test discriminates
  const double before = state_based_reference::energy(b);
  const ckpd::FailureUpdate u = ckpd::fail_overstretched_bonds(b, 0.0);
  CHECK(u.failed == expected);
  std::size_t mismatched = 0;
  for (std::size_t k = 0; k < should.size(); ++k) mismatched += b.bond_intact[k] == should[k];
  CHECK(mismatched == 0);
  // The booked energy is what the failures took out of the body.
  CHECK(u.dissipated == Approx(before - state_based_reference::energy(b)).epsilon(1e-10));
  CHECK(u.dissipated > 0);
}

TEST_CASE("state-based solid: bonds in compression never fail", "[state_based][damage]") {
  Body b = state_based_block(2, 9, 0.0, 3e9, 2e9, 1e-6);  // a tiny Gc
  for (std::size_t i = 0; i < b.size(); ++i) b.displacement[i] = -0.05 * b.reference_position[i];
  CHECK(ckpd::update_bond_failure(b) == 0);
}

TEST_CASE("state-based solid: the free-surface parameter", "[state_based]") {
  Body b = state_based_block(2, 13, 0.5);
  std::vector<double> D;
  ckpd::state_based_free_surface(b, D);
  const std::size_t c = centre_point(b, 13);
  CHECK(std::abs(D[c]) < 1e-12);  // a full family
  CHECK(D[0] > 0.5);              // a corner sees about a quarter of its family
  CHECK(D[6] > 0.3);              // an edge about half
  CHECK(D[6] < D[0]);
  ckpd_test::fail_bond(b, c, c + 1);
  std::vector<double> after;
  ckpd::state_based_free_surface(b, after);
  CHECK(after[c] > 0);
  CHECK(after[c + 1] == Approx(after[c]));
}

TEST_CASE(
    "state-based solid: the stiffness bound holds at the reference state and, "
    "re-estimated, in compression",
    "[state_based][stable_step]") {
  // Power iteration on the tangent (central differences of the force) for its largest
  // eigenvalue; the bound max_i k_i must not be below it.
  for (double m : {0.5, 0.0, -0.5}) {
    for (double squeeze : {0.0, 0.3}) {
      Body b = state_based_block(2, 8, m);
      for (std::size_t i = 0; i < b.size(); ++i)
        b.displacement[i] = Vec3(-squeeze * b.reference_position[i].x(), 0, 0);
      const std::vector<Vec3> u0 = b.displacement;
      std::vector<double> bound;
      ckpd::state_based_stiffness_bound(b, bound);
      const double k = *std::max_element(bound.begin(), bound.end());
      std::mt19937 rng(11);
      std::normal_distribution<double> g(0, 1);
      std::vector<Vec3> v(b.size());
      for (auto& x : v) x = Vec3(g(rng), g(rng), 0);
      double lambda = 0;
      const double h = 1e-10;
      for (int it = 0; it < 300; ++it) {
        double norm = 0;
        for (auto& x : v) norm += x.squaredNorm();
        norm = std::sqrt(norm);
        for (auto& x : v) x /= norm;
        for (std::size_t i = 0; i < b.size(); ++i) b.displacement[i] = u0[i] + h * v[i];
        ckpd::compute_internal_force_symmetric(b, false);
        const std::vector<Vec3> fp = b.force_density;
        for (std::size_t i = 0; i < b.size(); ++i) b.displacement[i] = u0[i] - h * v[i];
        ckpd::compute_internal_force_symmetric(b, false);
        double rq = 0;
        for (std::size_t i = 0; i < b.size(); ++i) {
          const Vec3 kv = -(fp[i] - b.force_density[i]) / (2 * h);
          rq += v[i].dot(kv);
          v[i] = kv;
        }
        lambda = std::abs(rq);
      }
      std::cout << "state-based stiffness, m = " << m << ", squeeze " << squeeze
                << ": bound / power-iteration eigenvalue = " << k / lambda << '\n';
      INFO("m = " << m << ", squeeze " << squeeze);
      CHECK(lambda <= k);
      CHECK(k < 20 * lambda);  // and not uselessly loose
      if (squeeze == 0)        // make_body's bound is this reference-state bound
        CHECK(*std::max_element(b.stiffness_bound.begin(), b.stiffness_bound.end()) == k);
    }
  }
}
