// The patch test (THEORY.md section 2): the reference numbers of THEORY.md, and other horizons
// and Poisson ratios against an independent computation on the infinite lattice written here.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "bodies/patch_test.hpp"

namespace {

using Mat3 = Eigen::Matrix3d;
using V3 = Eigen::Vector3d;

struct Expected {
  std::uint64_t n1 = 0, n2 = 0, n3 = 0;
  double volumetric = 0, shear = 0, uniaxial = 0;
};

// Everything from THEORY.md directly: lattice offsets of the infinite unit lattice within m,
// ordered non-degenerate pairs and triples, psi1..psi3 for x = (I + e) X summed with
// dVn = VH^n / Nn (beta = 1), the constants of section 3 and the continuum energy.
class InfiniteLatticePatch {
 public:
  InfiniteLatticePatch(int dimension, double m, double E, double nu, bool plane_stress)
      : dim_(dimension), m_(m) {
    const double pi = std::numbers::pi;
    mu_ = E / (2 * (1 + nu));
    lambda_ = (dimension == 2 && plane_stress) ? E * nu / (1 - nu * nu)
                                               : E * nu / ((1 + nu) * (1 - 2 * nu));
    if (dimension == 3) {
      c1_ = 30 * mu_ / (pi * std::pow(m, 4));
      c3_ = 32 * (lambda_ - mu_) / (std::pow(pi, 4) * std::pow(m, 12));
      vh_ = 4.0 / 3.0 * pi * m * m * m;
    } else {
      c1_ = 24 * mu_ / (pi * std::pow(m, 3));
      c2_ = 27 * (lambda_ - mu_) / (8 * pi * std::pow(m, 6));
      vh_ = pi * m * m;
    }
    const int h = static_cast<int>(std::ceil(m));
    const int zr = dimension == 3 ? h : 0;
    for (int z = -zr; z <= zr; ++z)
      for (int y = -h; y <= h; ++y)
        for (int x = -h; x <= h; ++x) {
          const V3 o(x, y, z);
          if ((x || y || z) && o.norm() <= m * (1 + 1e-12)) offsets_.push_back(o);
        }
    const std::size_t n = offsets_.size();
    auto near = [&](std::size_t a, std::size_t b) {
      return (offsets_[a] - offsets_[b]).norm() <= m * (1 + 1e-12);
    };
    for (std::size_t j = 0; j < n; ++j)
      for (std::size_t k = 0; k < n; ++k) {
        if (j == k || !near(j, k)) continue;
        const V3 &p = offsets_[j], &q = offsets_[k];
        if (p.cross(q).norm() > 1e-10 * p.norm() * q.norm()) pairs_.push_back({j, k});
        if (dimension == 2) continue;
        for (std::size_t l = 0; l < n; ++l) {
          if (l == j || l == k || !near(j, l) || !near(k, l)) continue;
          const V3& r = offsets_[l];
          if (std::abs(p.cross(q).dot(r)) > 1e-10 * p.norm() * q.norm() * r.norm())
            triples_.push_back({j, k, l});
        }
      }
  }

  std::uint64_t n1() const { return offsets_.size(); }
  std::uint64_t n2() const { return pairs_.size(); }
  std::uint64_t n3() const { return triples_.size(); }

  // (W1/2 + W2/3 + W3/4) / (lambda/2 tr(e)^2 + mu e:e).
  double ratio(const Mat3& e) const {
    const Mat3 F = Mat3::Identity() + e;
    double w1 = 0, w2 = 0, w3 = 0;
    for (const V3& o : offsets_) {
      const double L = o.norm(), l = (F * o).norm();
      w1 += c1_ * L * (l / L - 1) * (l / L - 1) / 2;
    }
    if (dim_ == 2) {
      for (const auto& [j, k] : pairs_) {
        const V3 &p = offsets_[j], &q = offsets_[k];
        const double A = p.cross(q).norm(), a = (F * p).cross(F * q).norm();
        w2 += c2_ * A * (a / A - 1) * (a / A - 1) / 2;
      }
    } else {
      for (const auto& [j, k, l] : triples_) {
        const V3 &p = offsets_[j], &q = offsets_[k], &r = offsets_[l];
        const double V = std::abs(p.cross(q).dot(r));
        const double v = std::abs((F * p).cross(F * q).dot(F * r));
        w3 += c3_ * V * (v / V - 1) * (v / V - 1) / 2;
      }
    }
    w1 *= vh_ / static_cast<double>(n1());
    if (n2() && dim_ == 2) w2 *= vh_ * vh_ / static_cast<double>(n2());
    if (n3()) w3 *= vh_ * vh_ * vh_ / static_cast<double>(n3());
    const double continuum =
        lambda_ / 2 * e.trace() * e.trace() + mu_ * (e.array() * e.array()).sum();
    return (w1 / 2 + w2 / 3 + w3 / 4) / continuum;
  }

  // Replaces the THEORY.md constants (for the calibration tests).
  void set_constants(double c1, double c2, double c3) {
    c1_ = c1;
    c2_ = c2;
    c3_ = c3;
  }

  Expected expected(double eps) const {
    Expected x{n1(), n2(), n3(), 0, 0, 0};
    Mat3 e = Mat3::Zero();
    for (int d = 0; d < dim_; ++d) e(d, d) = eps;
    x.volumetric = ratio(e);
    e.setZero();
    e(0, 1) = e(1, 0) = eps;
    x.shear = ratio(e);
    e.setZero();
    e(0, 0) = eps;
    x.uniaxial = ratio(e);
    return x;
  }

 private:
  int dim_;
  double m_;
  double mu_ = 0, lambda_ = 0, c1_ = 0, c2_ = 0, c3_ = 0, vh_ = 0;
  std::vector<V3> offsets_;
  std::vector<std::array<std::size_t, 2>> pairs_;
  std::vector<std::array<std::size_t, 3>> triples_;
};

void check_ratios(const ckpd::PatchTestResult& r, const Expected& x, double tolerance) {
  CHECK(r.n1 == x.n1);
  CHECK(r.n2 == x.n2);
  CHECK(r.n3 == x.n3);
  CHECK(r.volumetric == Approx(x.volumetric).epsilon(0).margin(tolerance));
  CHECK(r.shear == Approx(x.shear).epsilon(0).margin(tolerance));
  CHECK(r.uniaxial == Approx(x.uniaxial).epsilon(0).margin(tolerance));
}

}  // namespace

TEST_CASE("patch test reproduces the MODEL.md 3D reference numbers", "[patch_test]") {
  const Expected model{122, 6552, 211968, 0.982277, 1.12305, 0.950992};
  const auto r = ckpd::run_patch_test(3, 3.015, 210e9, 0.3, ckpd::PlaneMode::none);
  check_ratios(r, model, 1e-4);
  // The independent infinite-lattice computation gives the same numbers.
  check_ratios(r, InfiniteLatticePatch(3, 3.015, 210e9, 0.3, false).expected(1e-6), 1e-6);
}

TEST_CASE("patch test reproduces the MODEL.md 2D plane-stress reference numbers", "[patch_test]") {
  const Expected model{28, 360, 0, 1.04253, 1.00992, 1.05625};
  const auto r = ckpd::run_patch_test(2, 3.015, 210e9, 0.3, ckpd::PlaneMode::stress);
  check_ratios(r, model, 1e-4);
  check_ratios(r, InfiniteLatticePatch(2, 3.015, 210e9, 0.3, true).expected(1e-6), 1e-6);
}

TEST_CASE("patch test matches an independent infinite-lattice computation for other m and nu",
          "[patch_test]") {
  struct Case {
    int dimension;
    double m, E, nu;
    ckpd::PlaneMode plane;
  };
  const std::vector<Case> cases = {
      {3, 2.5, 210e9, 0.2, ckpd::PlaneMode::none},       // C3 < 0
      {3, 2.015, 70e9, 0.4, ckpd::PlaneMode::none},      // C3 > 0
      {2, 4.015, 210e9, 0.25, ckpd::PlaneMode::strain},  // lambda = mu: C2 = 0
      {2, 3.015, 190e9, 0.3, ckpd::PlaneMode::strain},   // C2 > 0
      {2, 2.6, 50e9, 0.4, ckpd::PlaneMode::stress},      // C2 > 0
      {2, 5.015, 210e9, 0.1, ckpd::PlaneMode::stress},   // C2 < 0
  };
  for (const Case& c : cases) {
    INFO("dimension " << c.dimension << ", m " << c.m << ", nu " << c.nu << ", plane "
                      << ckpd::to_string(c.plane));
    const auto r = ckpd::run_patch_test(c.dimension, c.m, c.E, c.nu, c.plane);
    const Expected x =
        InfiniteLatticePatch(c.dimension, c.m, c.E, c.nu, c.plane == ckpd::PlaneMode::stress)
            .expected(1e-6);
    check_ratios(r, x, 1e-6);
    // The ratios are a property of the discretisation: near 1, never wildly off.
    CHECK(std::abs(r.volumetric - 1) < 0.5);
    CHECK(std::abs(r.shear - 1) < 0.5);
    CHECK(std::abs(r.uniaxial - 1) < 0.5);
  }
}

TEST_CASE("patch-test ratios are a small-strain limit independent of the strain size",
          "[patch_test]") {
  const auto a = ckpd::run_patch_test(2, 3.015, 210e9, 0.3, ckpd::PlaneMode::stress, 1e-6);
  const auto b = ckpd::run_patch_test(2, 3.015, 210e9, 0.3, ckpd::PlaneMode::stress, 1e-7);
  CHECK(a.volumetric == Approx(b.volumetric).epsilon(1e-5));
  CHECK(a.shear == Approx(b.shear).epsilon(1e-5));
  CHECK(a.uniaxial == Approx(b.uniaxial).epsilon(1e-5));
}

// Calibrated constants (`constants: calibrated`): C1 and C3 (C2 in 2D) solved so that the
// lattice's volumetric and uniaxial energies equal the continuum's.
TEST_CASE("calibrated constants give volumetric and uniaxial ratios of 1 on their lattice",
          "[patch_test][calibration]") {
  struct Case {
    int dimension;
    double m, nu;
    ckpd::PlaneMode plane;
  };
  const std::vector<Case> cases = {
      {3, 2.015, 0.3, ckpd::PlaneMode::none},       {3, 3.015, 0.3, ckpd::PlaneMode::none},
      {3, 2.015, 0.05, ckpd::PlaneMode::none},  // analytic C3 < 0
      {3, 2.015, 0.25, ckpd::PlaneMode::none},  // analytic C3 = 0: solved, not scaled
      {3, 1.5, 0.49, ckpd::PlaneMode::none},    // large C3; smallest m with triples
      {2, 3.015, 0.3, ckpd::PlaneMode::stress},     {2, 4.015, 0.1, ckpd::PlaneMode::stress},
      {2, 2.015, 1.0 / 3, ckpd::PlaneMode::stress},  // analytic C2 = 0
      {2, 3.015, 0.45, ckpd::PlaneMode::strain},
  };
  for (const Case& c : cases) {
    INFO("dimension " << c.dimension << ", m " << c.m << ", nu " << c.nu);
    const double E = 210e9;
    const ckpd::InteractionConstants cal =
        ckpd::calibrated_constants(c.dimension, E, c.nu, c.plane, c.m, 1.0);
    const auto r = ckpd::run_patch_test(c.dimension, c.m, E, c.nu, c.plane, cal);
    CHECK(std::abs(r.volumetric - 1) < 1e-3);
    CHECK(std::abs(r.uniaxial - 1) < 1e-3);
    // The independent infinite-lattice computation with the same constants agrees.
    InfiniteLatticePatch independent(c.dimension, c.m, E, c.nu, c.plane == ckpd::PlaneMode::stress);
    independent.set_constants(cal.c1, cal.c2, cal.c3);
    const Expected x = independent.expected(1e-6);
    CHECK(std::abs(x.volumetric - 1) < 1e-3);
    CHECK(std::abs(x.uniaxial - 1) < 1e-3);
    CHECK(r.shear == Approx(x.shear).epsilon(0).margin(1e-6));
    if (c.nu == 0.25 && c.dimension == 3) CHECK(cal.c3 != 0);
  }
}

TEST_CASE("calibrated constants scale with the spacing like the analytic ones",
          "[patch_test][calibration]") {
  const double dx = 2.5e-3, m = 3.015;
  for (int dim : {2, 3}) {
    const auto plane = dim == 2 ? ckpd::PlaneMode::stress : ckpd::PlaneMode::none;
    const auto unit = ckpd::calibrated_constants(dim, 200e9, 0.3, plane, m, 1.0);
    const auto real = ckpd::calibrated_constants(dim, 200e9, 0.3, plane, m * dx, dx);
    const auto a_unit = ckpd::interaction_constants(dim, 200e9, 0.3, plane, m);
    const auto a_real = ckpd::interaction_constants(dim, 200e9, 0.3, plane, m * dx);
    // The calibrated-to-analytic scale factors are properties of the lattice and m only.
    CHECK(real.c1 / a_real.c1 == Approx(unit.c1 / a_unit.c1).epsilon(1e-9));
    if (dim == 2) CHECK(real.c2 / a_real.c2 == Approx(unit.c2 / a_unit.c2).epsilon(1e-9));
    if (dim == 3) CHECK(real.c3 / a_real.c3 == Approx(unit.c3 / a_unit.c3).epsilon(1e-9));
  }
}

TEST_CASE("calibration without three-neighbour sets is refused with a reason",
          "[patch_test][calibration]") {
  // At m = 1.2 an interior point's bonds are the 6 axis neighbours: no tetrahedron fits.
  CHECK_THROWS_WITH(ckpd::calibrated_constants(3, 200e9, 0.3, ckpd::PlaneMode::none, 1.2, 1.0),
                    Catch::Contains("N3 = 0"));
  CHECK_THROWS_WITH(ckpd::calibrated_constants(2, 200e9, 0.3, ckpd::PlaneMode::stress, 1.2, 1.0),
                    Catch::Contains("N2 = 0"));
}
