// The Seth-Hill strain measure of the CKPD model (bodies/ckpd_model.hpp, CkpdSethHillModel),
// against references that do not come from it: for m = 1/2, 0 and -1/2, in 2D and 3D, each
// family's vertex forces are minus the finite-difference gradient of its energy, the energy is
// C R e_m(r)^2 / 2 written with std::pow / std::log, the linearisation at the reference state
// (the stiffness bound's input) is the same for every m, m = 1/2 is the default law, and the
// patch test's ratios are m = 1/2's to first order in the strain.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

#include "bodies/ckpd_model.hpp"
#include "bodies/patch_test.hpp"
#include "set_term_checks.hpp"

namespace {

using ckpd::CkpdModel;
using ckpd::CkpdSethHillModel;
using ckpd::Vec3;
using namespace set_term_checks;

constexpr double kMeasures[] = {0.5, 0.0, -0.5};

const ckpd::InteractionConstants kConstants{1.7e18, -2.3e24, 4.1e30};
const ckpd::InteractionConstants kPlanarConstants{1.7e18, 2.3e24, 0};

CkpdSethHillModel seth_hill(double m, double penalty = 0, bool planar = false) {
  return CkpdSethHillModel(planar ? kPlanarConstants : kConstants, penalty, planar, 0.01, m);
}

// e_m(r) = (r^(2m) - 1) / (2m), e_0 = log r, written directly.
double seth_hill_strain(double m, double r) {
  return m == 0 ? std::log(r) : (std::pow(r, 2 * m) - 1) / (2 * m);
}

// In-plane points (2D bodies).
std::vector<Vec3> flattened(std::vector<Vec3> x) {
  for (Vec3& p : x) p.z() = 0;
  return x;
}

TermOf<2> bond_of(const CkpdSethHillModel& model) {
  return [&model](const std::vector<Vec3>& X, const std::vector<Vec3>& x) {
    return model.bond_term(X[1] - X[0], x[1] - x[0]);
  };
}
TermOf<3> triangle_of(const CkpdSethHillModel& model) {
  return [&model](const std::vector<Vec3>& X, const std::vector<Vec3>& x) {
    const auto P = offsets(X), p = offsets(x);
    return model.triangle_term(P[0], P[1], p[0], p[1], kDegenerate);
  };
}
TermOf<4> tetrahedron_of(const CkpdSethHillModel& model) {
  return [&model](const std::vector<Vec3>& X, const std::vector<Vec3>& x) {
    const auto P = offsets(X), p = offsets(x);
    return model.tetrahedron_term(P[0], P[1], P[2], p[0], p[1], p[2], kDegenerate);
  };
}

}  // namespace

TEST_CASE("Seth-Hill bond force is minus the gradient of C1 L e_m^2 / 2, 2D and 3D",
          "[strain_measure]") {
  std::mt19937 rng(21);
  for (const double m : kMeasures) {
    const CkpdSethHillModel model = seth_hill(m);
    const TermOf<2> term = bond_of(model);
    for (int trial = 0; trial < 20; ++trial) {
      std::vector<Vec3> X = random_points(rng, 2, 1e-3);
      if (trial % 2) X = flattened(X);
      // A few per cent, and up to tens of per cent of compression and extension.
      const std::vector<Vec3> x = strained(rng, X, trial < 10 ? 3e-5 : 2e-4);
      INFO("m = " << m << ", trial " << trial);
      check_forces_are_minus_energy_gradient<2>(term, X, x, 1e-3);
      const double L = (X[1] - X[0]).norm(), r = (x[1] - x[0]).norm() / L;
      const double e = seth_hill_strain(m, r);
      CHECK(term(X, x).energy == Approx(model.c1 * L * e * e / 2).epsilon(1e-9));
      CHECK(term(X, X).energy == 0);
    }
  }
}

TEST_CASE("Seth-Hill triangle forces are minus the gradient of its energy, 2D with penalty",
          "[strain_measure]") {
  std::mt19937 rng(22);
  for (const double m : kMeasures) {
    for (const bool planar : {false, true}) {
      const CkpdSethHillModel model = seth_hill(m, planar ? 1.0 : 0.0, planar);
      const TermOf<3> term = triangle_of(model);
      int inverted = 0;
      for (int trial = 0; trial < 20; ++trial) {
        std::vector<Vec3> X = random_points(rng, 3, 1e-3);
        if (planar) X = flattened(X);
        std::vector<Vec3> x = strained(rng, X, trial < 10 ? 3e-5 : 1e-4);
        if (planar) x = flattened(x);
        if (planar && trial % 2) std::swap(x[1], x[2]);  // mirror image: inverted in the plane
        INFO("m = " << m << ", planar " << planar << ", trial " << trial);
        const ckpd::SetTerm<3> t = term(X, x);
        inverted += t.inverted;
        check_forces_are_minus_energy_gradient<3>(term, X, x, 1e-3);
        if (!t.inverted) {
          const auto P = offsets(X), p = offsets(x);
          const double A = P[0].cross(P[1]).norm(),
                       e = seth_hill_strain(m, p[0].cross(p[1]).norm() / A);
          CHECK(t.energy == Approx(A * e * e / 2).epsilon(1e-9));
        }
      }
      if (planar) CHECK(inverted >= 8);
    }
  }
}

TEST_CASE("Seth-Hill tetrahedron forces are minus the gradient of its energy, penalty included",
          "[strain_measure]") {
  std::mt19937 rng(23);
  for (const double m : kMeasures) {
    for (const double penalty : {0.0, 1.0}) {
      const CkpdSethHillModel model = seth_hill(m, penalty);
      const TermOf<4> term = tetrahedron_of(model);
      int inverted = 0;
      for (int trial = 0; trial < 20; ++trial) {
        const std::vector<Vec3> X = random_points(rng, 4, 1e-3);
        std::vector<Vec3> x = strained(rng, X, trial < 10 ? 3e-5 : 1e-4);
        if (trial % 2) std::swap(x[1], x[2]);
        INFO("m = " << m << ", penalty " << penalty << ", trial " << trial);
        const ckpd::SetTerm<4> t = term(X, x);
        inverted += t.inverted;
        check_forces_are_minus_energy_gradient<4>(term, X, x, 1e-3);
        if (!t.inverted) {
          const auto P = offsets(X), p = offsets(x);
          const double V = std::abs(P[0].dot(P[1].cross(P[2])));
          const double e = seth_hill_strain(m, std::abs(p[0].dot(p[1].cross(p[2]))) / V);
          CHECK(t.energy == Approx(V * e * e / 2).epsilon(1e-9));
        }
      }
      CHECK(inverted >= 8);
    }
  }
}

TEST_CASE("Seth-Hill linearisation at the reference state is the same for every m",
          "[strain_measure]") {
  // The linearisation (and so the stiffness bound and stable step) is m-independent because
  // e_m'(1) = 1: each m's force Jacobian, by finite differences, matches the one linearisation.
  std::mt19937 rng(24);
  const CkpdModel linear(kConstants, 0, false, 0.01);
  // Well-shaped sets only: on a nearly flat random set the finite-difference step is not small
  // against the set's own size and the O(h^2) error of the difference dominates.
  const auto well_shaped = [&rng](int count) {
    for (;;) {
      const std::vector<Vec3> X = random_points(rng, count, 1e-3);
      const auto P = offsets(X);
      const double measure = count == 3 ? P[0].cross(P[1]).norm() / (P[0].norm() * P[1].norm())
                                        : std::abs(P[0].dot(P[1].cross(P[2]))) /
                                              (P[0].norm() * P[1].norm() * P[2].norm());
      if (measure > 0.3) return X;
    }
  };
  for (const double m : kMeasures) {
    const CkpdSethHillModel model = seth_hill(m);
    INFO("m = " << m);
    for (int trial = 0; trial < 5; ++trial) {
      const std::vector<Vec3> X2 = random_points(rng, 2, 1e-3);
      check_linearisation_is_force_jacobian<2>(bond_of(model),
                                               linear.bond_linearisation(X2[1] - X2[0]), X2, 1e-3);
      const std::vector<Vec3> X3 = well_shaped(3);
      const auto P3 = offsets(X3);
      check_linearisation_is_force_jacobian<3>(
          triangle_of(model), linear.triangle_linearisation(P3[0], P3[1]), X3, 1e-3);
      const std::vector<Vec3> X4 = well_shaped(4);
      const auto P4 = offsets(X4);
      check_linearisation_is_force_jacobian<4>(
          tetrahedron_of(model), linear.tetrahedron_linearisation(P4[0], P4[1], P4[2]), X4, 1e-3);
    }
  }
}

TEST_CASE("Seth-Hill law with m = 1/2 is the default CKPD law to rounding", "[strain_measure]") {
  std::mt19937 rng(25);
  const CkpdModel linear(kConstants, 1.0, false, 0.01);
  const CkpdSethHillModel half = seth_hill(0.5, 1.0);
  for (int trial = 0; trial < 10; ++trial) {
    const std::vector<Vec3> X = random_points(rng, 4, 1e-3);
    std::vector<Vec3> x = strained(rng, X, 5e-5);
    if (trial % 2) std::swap(x[1], x[2]);
    const auto P = offsets(X), p = offsets(x);
    const auto a = linear.tetrahedron_term(P[0], P[1], P[2], p[0], p[1], p[2], kDegenerate);
    const auto b = half.tetrahedron_term(P[0], P[1], P[2], p[0], p[1], p[2], kDegenerate);
    for (int c = 0; c < 4; ++c)
      CHECK((a.force[c] - b.force[c]).norm() <= 1e-12 * a.force[0].norm());
    CHECK(b.energy == Approx(a.energy).epsilon(1e-12));
    const auto ta = linear.triangle_term(P[0], P[1], p[0], p[1], kDegenerate);
    const auto tb = half.triangle_term(P[0], P[1], p[0], p[1], kDegenerate);
    for (int c = 0; c < 3; ++c)
      CHECK((ta.force[c] - tb.force[c]).norm() <= 1e-12 * ta.force[0].norm());
    const auto ba = linear.bond_term(P[0], p[0]), bb = half.bond_term(P[0], p[0]);
    CHECK((ba.force[0] - bb.force[0]).norm() <= 1e-12 * ba.force[0].norm());
    CHECK(bb.energy == Approx(ba.energy).epsilon(1e-12));
  }
}

TEST_CASE("Seth-Hill measures with m <= 0 resist collapse without bound", "[strain_measure]") {
  // A bond compressed to ratio r: m = 1/2's restoring force stays below C1 (|dpsi/dl| = C1 |r-1|),
  // m = 0's is C1 |log r| / r and grows without bound as r -> 0, and its energy too.
  const CkpdSethHillModel log_measure = seth_hill(0.0), half = seth_hill(0.5);
  const Vec3 P(1e-3, 0, 0);
  double previous = 0;
  for (const double r : {0.5, 0.1, 0.01, 1e-4}) {
    const Vec3 p = r * P;
    const double f0 = log_measure.bond_term(P, p).force[0].norm(),
                 fh = half.bond_term(P, p).force[0].norm();
    CHECK(fh <= half.c1 * (1 - r) * (1 + 1e-12));
    CHECK(f0 == Approx(log_measure.c1 * std::abs(std::log(r)) / r).epsilon(1e-12));
    CHECK(f0 > previous);
    previous = f0;
  }
  // psi = C1 L (log r)^2 / 2 against C1 L (r - 1)^2 / 2 <= C1 L / 2.
  const double L = P.norm();
  CHECK(log_measure.bond_term(P, 1e-4 * P).energy ==
        Approx(log_measure.c1 * L * std::log(1e-4) * std::log(1e-4) / 2).epsilon(1e-12));
  CHECK(log_measure.bond_term(P, 1e-4 * P).energy > 50 * half.bond_term(P, 1e-4 * P).energy);
}

TEST_CASE("Seth-Hill patch test ratios equal m = 1/2's to first order at strain 1e-6",
          "[strain_measure]") {
  // e_m(r)^2 = (r - 1)^2 (1 + (2m - 1)(r - 1) + O((r - 1)^2)), and r - 1 is up to s for a bond,
  // 2s for an area and 3s for a volume: the ratios differ from m = 1/2's by a relative
  // |2m - 1| d s at most (d the dimension), 3e-6 (m = 0) and 6e-6 (m = -1/2) in 3D.
  struct Setting {
    int dimension;
    double nu;
    ckpd::PlaneMode plane;
  };
  const double strain = 1e-6;
  for (const Setting s :
       {Setting{3, 0.3, ckpd::PlaneMode::none}, Setting{3, 0.1, ckpd::PlaneMode::none},
        Setting{2, 0.2, ckpd::PlaneMode::stress}}) {
    const ckpd::InteractionConstants c =
        ckpd::interaction_constants(s.dimension, 210e9, s.nu, s.plane, 3.015);
    const ckpd::PatchTestResult base =
        ckpd::run_patch_test(s.dimension, 3.015, 210e9, s.nu, s.plane, c, strain, 0.5);
    for (const double m : {0.0, -0.5}) {
      const ckpd::PatchTestResult r =
          ckpd::run_patch_test(s.dimension, 3.015, 210e9, s.nu, s.plane, c, strain, m);
      const double bound = s.dimension * std::abs(2 * m - 1) * strain;
      INFO(s.dimension << "D nu " << s.nu << ", m = " << m << ": volumetric " << r.volumetric
                       << " vs " << base.volumetric << ", shear " << r.shear << " vs " << base.shear
                       << ", uniaxial " << r.uniaxial << " vs " << base.uniaxial);
      CHECK(std::abs(r.volumetric / base.volumetric - 1) <= bound);
      CHECK(std::abs(r.shear / base.shear - 1) <= bound);
      CHECK(std::abs(r.uniaxial / base.uniaxial - 1) <= bound);
      CHECK(r.volumetric != base.volumetric);  // the measure is in use
      // At strain 1e-9 the difference is 1e-9 relative: the constants match as s -> 0.
      const ckpd::PatchTestResult tiny =
          ckpd::run_patch_test(s.dimension, 3.015, 210e9, s.nu, s.plane, c, 1e-9, m);
      const ckpd::PatchTestResult tiny_base =
          ckpd::run_patch_test(s.dimension, 3.015, 210e9, s.nu, s.plane, c, 1e-9, 0.5);
      CHECK(std::abs(tiny.volumetric / tiny_base.volumetric - 1) <= 1e-8);
      CHECK(std::abs(tiny.uniaxial / tiny_base.uniaxial - 1) <= 1e-8);
    }
  }
}
