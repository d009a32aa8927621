// Per-point stress (bodies/point_stress.hpp, THEORY.md section 9): the virial of a point's own
// energy. Checked against
// - the continuum stress times the patch-test ratio at an interior lattice point under a
//   homogeneous small strain (the ratio comes from the patch test's energies, another code path);
// - finite differences of the point's energy density in F under a finite homogeneous
//   deformation (tau = dW/dF F^T), surface points included;
// - the virial of the body's total strain energy (finite differences) for a random, non-
//   homogeneous deformation with failed bonds: sum_i V^i tau^i = sum_k dE/dx^k (x) x^k;
// - the virial of the optimised kernel's own forces where the model is conservative (bonds only
//   on a lattice, where every dV1 is equal): sum_i V^i tau^i = -sum_k V^k b^k (x) x^k.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "bodies/patch_test.hpp"
#include "bodies/point_kernel.hpp"
#include "bodies/point_stress.hpp"
#include "bodies/state_based_model.hpp"
#include "bodies/symmetric_kernel.hpp"
#include "body_fixtures.hpp"

using namespace ckpd;
using ckpd_test::jittered_cloud;
using ckpd_test::lattice_block;

namespace {

void deform(Body& body, const Eigen::Matrix3d& F) {
  for (std::size_t i = 0; i < body.size(); ++i)
    body.displacement[i] = (F - Eigen::Matrix3d::Identity()) * body.reference_position[i];
}

double point_energy(const Body& body, std::size_t i) {
  FamilyScratch s;
  return evaluate_point(body, i, s).strain_energy_density();
}

double total_energy(const Body& body) {
  double e = 0;
  for (std::size_t i = 0; i < body.size(); ++i) e += body.volume[i] * point_energy(body, i);
  return e;
}

double max_abs(const Eigen::Matrix3d& m) {
  return m.cwiseAbs().maxCoeff();
}

// dW/dF F^T of a point's energy density W(F) under x = F X, by central differences in each
// in-plane component of F: the Kirchhoff stress of a homogeneous deformation.
template <class Energy>
Eigen::Matrix3d kirchhoff_by_differences(Body& body, const Eigen::Matrix3d& F, Energy energy) {
  Eigen::Matrix3d dWdF = Eigen::Matrix3d::Zero();
  const double h = 1e-6;
  for (int r = 0; r < body.dimension; ++r)
    for (int c = 0; c < body.dimension; ++c) {
      Eigen::Matrix3d Fp = F, Fm = F;
      Fp(r, c) += h;
      Fm(r, c) -= h;
      deform(body, Fp);
      const double wp = energy();
      deform(body, Fm);
      const double wm = energy();
      dWdF(r, c) = (wp - wm) / (2 * h);
    }
  deform(body, F);
  return dWdF * F.transpose();
}

}  // namespace

TEST_CASE("interior point stress is the continuum stress times the patch-test ratio", "[stress]") {
  const double E = 210e9, nu = 0.3;
  for (int dim : {2, 3}) {
    INFO(dim << "D");
    const double m = dim == 3 ? 3.015 : 3.015, dx = 1e-3;
    const PlaneMode plane = dim == 2 ? PlaneMode::stress : PlaneMode::none;
    const int n = 7;  // the centre (3, 3, 3) has a full family
    Body body = make_body(lattice_block(dim, n, n, dim == 3 ? n : 1, dx, m,
                                        interaction_constants(dim, E, nu, plane, m * dx)));
    const std::size_t centre = dim == 3 ? 3 + 7 * 3 + 49 * 3 : 3 + 7 * 3;
    REQUIRE(body.beta[centre] == Approx(1));
    const PatchTestResult ratio = run_patch_test(dim, m, E, nu, plane);
    const ElasticModuli moduli = elastic_moduli(dim, E, nu, plane);
    const double eps = 1e-6;
    auto continuum = [&](const Eigen::Matrix3d& e) {
      Eigen::Matrix3d s = 2 * moduli.mu * e;
      for (int d = 0; d < dim; ++d) s(d, d) += moduli.lambda * e.trace();
      return s;
    };
    auto stress_at = [&](const Eigen::Matrix3d& e) {
      deform(body, Eigen::Matrix3d::Identity() + e);
      FamilyScratch s;
      return point_kirchhoff_stress(body, centre, s);
    };
    Eigen::Matrix3d vol = Eigen::Matrix3d::Zero(), shear = vol, uni = vol;
    for (int d = 0; d < dim; ++d) vol(d, d) = eps;
    shear(0, 1) = shear(1, 0) = eps;
    uni(0, 0) = eps;
    // Volumetric: the whole tensor (cubic symmetry makes it isotropic).
    const Eigen::Matrix3d tv = stress_at(vol), cv = continuum(vol);
    CHECK(max_abs(tv - ratio.volumetric * cv) < 1e-5 * max_abs(cv));
    // Shear: the xy component; nothing on the diagonal.
    const Eigen::Matrix3d ts = stress_at(shear), cs = continuum(shear);
    CHECK(ts(0, 1) == Approx(ratio.shear * cs(0, 1)).epsilon(1e-5));
    CHECK(ts.diagonal().cwiseAbs().maxCoeff() < 1e-5 * cs(0, 1));
    // Uniaxial: the component along the strain (e : tau = 2 W for a quadratic energy).
    const Eigen::Matrix3d tu = stress_at(uni), cu = continuum(uni);
    CHECK(tu(0, 0) == Approx(ratio.uniaxial * cu(0, 0)).epsilon(1e-5));
    CHECK(max_abs(tu - tu.transpose()) < 1e-9 * max_abs(tu));
  }
}

TEST_CASE("point stress is dW/dF F^T under a finite homogeneous deformation", "[stress]") {
  std::mt19937 rng(11);
  for (int dim : {2, 3}) {
    INFO(dim << "D");
    const double dx = 1e-3, m = dim == 3 ? 2.015 : 3.015;
    const PlaneMode plane = dim == 2 ? PlaneMode::stress : PlaneMode::none;
    // nu = 0.3: C2 > 0 (2D), C3 > 0 (3D); every family is built.
    BodyDefinition def =
        jittered_cloud(dim, 6, 5, dim == 3 ? 4 : 1, dx, m,
                       interaction_constants(dim, 70e9, 0.3, plane, m * dx), 0.2, rng);
    Body body = make_body(def);
    std::uniform_real_distribution<double> u(-0.08, 0.08);
    Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
    for (int r = 0; r < dim; ++r)
      for (int c = 0; c < dim; ++c) F(r, c) += u(rng);
    for (std::size_t i : {std::size_t{0}, std::size_t{7}, body.size() / 2}) {
      INFO("point " << i);
      deform(body, F);
      FamilyScratch s;
      const Eigen::Matrix3d tau = point_kirchhoff_stress(body, i, s);
      const Eigen::Matrix3d expected =
          kirchhoff_by_differences(body, F, [&] { return point_energy(body, i); });
      CHECK(max_abs(tau - expected) < 1e-6 * max_abs(expected));
      CHECK(max_abs(tau - tau.transpose()) < 1e-9 * max_abs(tau));
    }
  }
}

TEST_CASE("the volume sum of point stresses is the virial of the total strain energy", "[stress]") {
  std::mt19937 rng(5);
  for (int dim : {2, 3}) {
    INFO(dim << "D");
    const double dx = 1e-3, m = dim == 3 ? 1.515 : 2.015;
    const PlaneMode plane = dim == 2 ? PlaneMode::stress : PlaneMode::none;
    BodyDefinition def =
        jittered_cloud(dim, 5, 4, dim == 3 ? 3 : 1, dx, m,
                       interaction_constants(dim, 70e9, 0.3, plane, m * dx), 0.2, rng);
    def.critical_stretch = 1;  // damage on, so failed bonds are left out
    Body body = make_body(def);
    ckpd_test::perturb(body, 0.03 * dx, rng);
    REQUIRE(ckpd_test::fail_random_bonds(body, 0.1, rng) > 0);
    Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
    std::vector<Eigen::Matrix3d> tau;
    kirchhoff_stress(body, tau);
    for (std::size_t i = 0; i < body.size(); ++i) sum += body.volume[i] * tau[i];
    Eigen::Matrix3d virial = Eigen::Matrix3d::Zero();
    const double h = 1e-9;
    for (std::size_t k = 0; k < body.size(); ++k) {
      Vec3 g = Vec3::Zero();
      for (int c = 0; c < dim; ++c) {
        const double keep = body.displacement[k][c];
        body.displacement[k][c] = keep + h;
        const double ep = total_energy(body);
        body.displacement[k][c] = keep - h;
        const double em = total_energy(body);
        body.displacement[k][c] = keep;
        g[c] = (ep - em) / (2 * h);
      }
      virial += g * body.current_position(k).transpose();
    }
    CHECK(max_abs(sum - virial) < 1e-5 * max_abs(virial));
  }
}

TEST_CASE("with bonds only on a lattice the point stresses sum to the kernel's force virial",
          "[stress]") {
  std::mt19937 rng(3);
  const double dx = 1e-3;
  Body body = make_body(lattice_block(3, 6, 5, 4, dx, 3.015, InteractionConstants{1e20, 0, 0}));
  ckpd_test::perturb(body, 0.01 * dx, rng);
  compute_internal_force_symmetric(body, false);
  Eigen::Matrix3d virial = Eigen::Matrix3d::Zero(), sum = virial;
  std::vector<Eigen::Matrix3d> tau;
  kirchhoff_stress(body, tau);
  for (std::size_t k = 0; k < body.size(); ++k) {
    virial -= body.volume[k] * body.force_density[k] * body.current_position(k).transpose();
    sum += body.volume[k] * tau[k];
  }
  CHECK(max_abs(sum - virial) < 1e-10 * max_abs(virial));
}

TEST_CASE(
    "under the energy-consistent form the point stresses of a damaged cloud sum to the kernel's "
    "force virial",
    "[stress]") {
  // The forces are the gradient of the energy whose virial the point stresses are, so the two
  // virials agree everywhere, surfaces and failed bonds included (the own-family form only in the
  // interior).
  std::mt19937 rng(9);
  for (int dim : {2, 3}) {
    INFO(dim << "D");
    const double dx = 1e-3, m = dim == 3 ? 1.515 : 2.015;
    const PlaneMode plane = dim == 2 ? PlaneMode::stress : PlaneMode::none;
    BodyDefinition def =
        jittered_cloud(dim, 5, 4, dim == 3 ? 3 : 1, dx, m,
                       interaction_constants(dim, 70e9, 0.3, plane, m * dx), 0.2, rng);
    def.critical_stretch = 1;
    def.force_form = ForceForm::energy_consistent;
    Body body = make_body(def);
    ckpd_test::perturb(body, 0.03 * dx, rng);
    REQUIRE(ckpd_test::fail_random_bonds(body, 0.1, rng) > 0);
    compute_internal_force_symmetric(body, false);
    Eigen::Matrix3d virial = Eigen::Matrix3d::Zero(), sum = virial;
    std::vector<Eigen::Matrix3d> tau;
    kirchhoff_stress(body, tau);
    for (std::size_t k = 0; k < body.size(); ++k) {
      virial -= body.volume[k] * body.force_density[k] * body.current_position(k).transpose();
      sum += body.volume[k] * tau[k];
    }
    CHECK(max_abs(sum - virial) < 1e-9 * max_abs(virial));
  }
}

TEST_CASE("a state-based point's stress is dpsi/dF F^T under a finite homogeneous deformation",
          "[stress][state_based]") {
  std::mt19937 rng(5);
  for (int dim : {2, 3}) {
    for (double m : {0.5, 0.0}) {
      INFO(dim << "D, m = " << m);
      const int n = dim == 3 ? 5 : 7;
      BodyDefinition def =
          lattice_block(dim, n, n, dim == 3 ? n : 1, 1e-3, 3.015, {0, 0, 0}, 1000.0);
      def.model = &state_based_kernels();
      def.state_based.lambda_bar = 3e9;
      def.state_based.mu_bar = 2e9;
      def.state_based.m = m;
      Body body = make_body(std::move(def));
      ckpd_test::fail_random_bonds(body, 0.15, rng);
      std::uniform_real_distribution<double> u(-0.08, 0.08);
      Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
      for (int r = 0; r < dim; ++r)
        for (int c = 0; c < dim; ++c) F(r, c) += u(rng);
      auto psi = [&](std::size_t i) {
        std::vector<double> w;
        state_based_energy_density(body, w);
        return w[i];
      };
      // A corner, an edge point and the centre.
      for (std::size_t i : {std::size_t{0}, std::size_t{3}, body.size() / 2}) {
        INFO("point " << i);
        deform(body, F);
        FamilyScratch s;
        const Eigen::Matrix3d tau = point_kirchhoff_stress(body, i, s);
        const Eigen::Matrix3d expected = kirchhoff_by_differences(body, F, [&] { return psi(i); });
        CHECK(max_abs(tau - expected) < 1e-6 * max_abs(expected));
        CHECK(max_abs(tau - tau.transpose()) < 1e-9 * max_abs(tau));
      }
    }
  }
}
