// The stable time-step estimate (THEORY.md section 6) against the true critical step of the
// linearised system rho u'' = -K u, K from a finite-difference Jacobian of the internal force.
#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "bodies/material.hpp"
#include "body_fixtures.hpp"
#include "reference/internal_force.hpp"

namespace {

using ckpd::Body;
using ckpd::PlaneMode;
using ckpd::Vec3;

// Largest real part of the eigenvalues of M^-1 K = K / rho, with K = -d b / d u about the
// reference configuration by central differences over the in-plane degrees of freedom. Moving
// point p changes only the forces of p and of its family members (b^i depends on x^j only for
// j in H1^i, and families are symmetric), so only those rows are evaluated.
double largest_eigenvalue(Body body) {
  const int dim = body.dimension;
  const std::size_t n = body.size() * static_cast<std::size_t>(dim);
  const double h = 1e-6 * body.horizon;
  ckpd::FamilyScratch scratch;
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n);
  for (std::size_t col = 0; col < n; ++col) {
    const std::size_t p = col / dim;
    const int c = static_cast<int>(col % dim);
    std::vector<std::size_t> rows(body.family.neighbour.begin() + body.family.offset[p],
                                  body.family.neighbour.begin() + body.family.offset[p + 1]);
    rows.push_back(p);
    std::vector<Vec3> plus(rows.size());
    body.displacement[p][c] = h;
    for (std::size_t r = 0; r < rows.size(); ++r)
      plus[r] = ckpd::evaluate_point(body, rows[r], scratch).force_density;
    body.displacement[p][c] = -h;
    for (std::size_t r = 0; r < rows.size(); ++r) {
      const Vec3 minus = ckpd::evaluate_point(body, rows[r], scratch).force_density;
      for (int e = 0; e < dim; ++e) K(rows[r] * dim + e, col) = -(plus[r][e] - minus[e]) / (2 * h);
    }
    body.displacement[p][c] = 0;
  }
  K /= body.density;
  const Eigen::EigenSolver<Eigen::MatrixXd> solver(K, false);
  return solver.eigenvalues().real().maxCoeff();
}

}  // namespace

TEST_CASE("the stable-step estimate is safe and not absurdly conservative", "[stable_step]") {
  const double dx = 1e-3, E = 210e9, rho = 7850;
  std::mt19937 rng(41);
  struct Case {
    std::string label;
    ckpd::BodyDefinition definition;
  };
  auto constants = [&](int dim, double nu, PlaneMode plane, double m) {
    return ckpd::interaction_constants(dim, E, nu, plane, m * dx);
  };
  const std::vector<Case> cases = {
      {"3D 5x5x5, m 2.015, nu 0.3 (C3 > 0)",
       ckpd_test::lattice_block(3, 5, 5, 5, dx, 2.015, constants(3, 0.3, PlaneMode::none, 2.015),
                                rho)},
      {"3D 4x4x4, m 2.015, nu 0.1 (C3 < 0)",
       ckpd_test::lattice_block(3, 4, 4, 4, dx, 2.015, constants(3, 0.1, PlaneMode::none, 2.015),
                                rho)},
      {"2D 8x8, m 3.015, plane stress nu 0.3 (C2 < 0)",
       ckpd_test::lattice_block(2, 8, 8, 1, dx, 3.015, constants(2, 0.3, PlaneMode::stress, 3.015),
                                rho)},
      {"2D 8x8, m 3.015, plane strain nu 0.4 (C2 > 0)",
       ckpd_test::lattice_block(2, 8, 8, 1, dx, 3.015, constants(2, 0.4, PlaneMode::strain, 3.015),
                                rho)},
      {"2D 8x8 jittered cloud, m 3.015, plane stress nu 0.2",
       ckpd_test::jittered_cloud(2, 8, 8, 1, dx, 3.015, constants(2, 0.2, PlaneMode::stress, 3.015),
                                 0.2, rng)},
  };
  for (const Case& c : cases) {
    ckpd::BodyDefinition d = c.definition;
    d.density = rho;
    const Body body = ckpd::make_body(d);
    const ckpd::StableStep estimate = ckpd::stable_step(body);
    const double lambda = largest_eigenvalue(body);
    REQUIRE(lambda > 0);
    const double critical = 2 / std::sqrt(lambda);
    INFO(c.label << ": dt_est " << estimate.dt << " s, true critical step " << critical
                 << " s, ratio " << estimate.dt / critical);
    CHECK(estimate.point < body.size());
    CHECK(estimate.dt <= critical);        // on the safe side
    CHECK(estimate.dt >= 0.3 * critical);  // and not absurdly so
  }
}

TEST_CASE("the stable step scales as sqrt(rho / E) and is infinite without stiffness",
          "[stable_step]") {
  const double m = 3.015;
  auto body_with = [&](double E, double rho) {
    ckpd::BodyDefinition d = ckpd_test::lattice_block(
        2, 6, 6, 1, 1e-3, m, ckpd::interaction_constants(2, E, 0.3, PlaneMode::stress, m * 1e-3),
        rho);
    return ckpd::make_body(d);
  };
  const double base = ckpd::stable_step(body_with(200e9, 8000)).dt;
  CHECK(ckpd::stable_step(body_with(800e9, 8000)).dt == Approx(base / 2).epsilon(1e-12));
  CHECK(ckpd::stable_step(body_with(200e9, 32000)).dt == Approx(base * 2).epsilon(1e-12));
  const Body inert = ckpd::make_body(ckpd_test::lattice_block(2, 4, 4, 1, 1e-3, m, {0, 0, 0}, 1));
  CHECK(std::isinf(ckpd::stable_step(inert).dt));
}
