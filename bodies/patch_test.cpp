#include "bodies/patch_test.hpp"

#include <Eigen/LU>
#include <cmath>
#include <stdexcept>
#include <string>

#include "bodies/body.hpp"
#include "bodies/point_kernel.hpp"

namespace ckpd {

namespace {

BodyDefinition lattice_block(int dimension, double m, InteractionConstants constants,
                             double strain_measure = 0.5) {
  const int h = static_cast<int>(std::ceil(m)) + 1;
  BodyDefinition d;
  d.name = "patch";
  d.dimension = dimension;
  d.density = 1;
  d.horizon = m;
  d.constants = constants;
  d.strain_measure = strain_measure;
  const int zr = dimension == 3 ? h : 0;
  std::size_t full = 0;
  // The centre point first, so it has index 0.
  d.reference_position.push_back(Vec3::Zero());
  for (int z = -zr; z <= zr; ++z)
    for (int y = -h; y <= h; ++y)
      for (int x = -h; x <= h; ++x) {
        const Vec3 p(x, y, z);
        if (x == 0 && y == 0 && z == 0) continue;
        d.reference_position.push_back(p);
        if (within_horizon(p, m)) ++full;
      }
  d.volume.assign(d.reference_position.size(), 1.0);
  d.full_family_volume = static_cast<double>(full);
  return d;
}

PointResult strained_centre(const Body& body, const Eigen::Matrix3d& e) {
  Body b = body;
  for (std::size_t i = 0; i < b.size(); ++i) b.displacement[i] = e * b.reference_position[i];
  FamilyScratch scratch;
  return evaluate_point(b, 0, scratch);
}

double continuum_energy(const Eigen::Matrix3d& e, const ElasticModuli& moduli) {
  return 0.5 * moduli.lambda * e.trace() * e.trace() + moduli.mu * (e.array() * e.array()).sum();
}

double energy_ratio(const Body& body, const Eigen::Matrix3d& e, const ElasticModuli& moduli) {
  return strained_centre(body, e).strain_energy_density() / continuum_energy(e, moduli);
}

Eigen::Matrix3d volumetric_strain(int dimension, double eps) {
  Eigen::Matrix3d e = Eigen::Matrix3d::Zero();
  for (int d = 0; d < dimension; ++d) e(d, d) = eps;
  return e;
}

Eigen::Matrix3d uniaxial_strain(double eps) {
  Eigen::Matrix3d e = Eigen::Matrix3d::Zero();
  e(0, 0) = eps;
  return e;
}

}  // namespace

PatchTestResult run_patch_test(int dimension, double m, double E, double nu, PlaneMode plane,
                               double eps) {
  if (!(m >= 1)) throw std::invalid_argument("horizon ratio m must be at least 1");
  return run_patch_test(dimension, m, E, nu, plane,
                        interaction_constants(dimension, E, nu, plane, m), eps);
}

PatchTestResult run_patch_test(int dimension, double m, double E, double nu, PlaneMode plane,
                               const InteractionConstants& c, double eps, double strain_measure) {
  if (!(m >= 1)) throw std::invalid_argument("horizon ratio m must be at least 1");
  const ElasticModuli moduli = elastic_moduli(dimension, E, nu, plane);

  PatchTestResult r;
  {  // Count every family, whatever the constants.
    InteractionConstants counting{1, 1, dimension == 3 ? 1.0 : 0.0};
    const Body counter = make_body(lattice_block(dimension, m, counting));
    r.n1 = static_cast<std::uint32_t>(counter.family.family_size(0));
    r.n2 = counter.n2[0];
    r.n3 = counter.n3[0];
  }
  const Body body = make_body(lattice_block(dimension, m, c, strain_measure));
  r.volumetric = energy_ratio(body, volumetric_strain(dimension, eps), moduli);
  Eigen::Matrix3d e = Eigen::Matrix3d::Zero();
  e(0, 1) = e(1, 0) = eps;
  r.shear = energy_ratio(body, e, moduli);
  r.uniaxial = energy_ratio(body, uniaxial_strain(eps), moduli);
  return r;
}

InteractionConstants calibrated_constants(int dimension, double E, double nu, PlaneMode plane,
                                          double horizon, double spacing) {
  if (!(spacing > 0) || !(horizon > 0))
    throw std::invalid_argument("calibration needs a positive spacing and horizon");
  const double m = horizon / spacing;
  if (!(m >= 1)) throw std::invalid_argument("horizon ratio m must be at least 1");
  const ElasticModuli moduli = elastic_moduli(dimension, E, nu, plane);
  // Unit constants on the unit lattice: each family's energy density per unit constant.
  const InteractionConstants unit{1, dimension == 2 ? 1.0 : 0.0, dimension == 3 ? 1.0 : 0.0};
  const Body body = make_body(lattice_block(dimension, m, unit));
  const double eps = 1e-6;
  const Eigen::Matrix3d strains[2] = {volumetric_strain(dimension, eps), uniaxial_strain(eps)};
  Eigen::Matrix2d a;
  Eigen::Vector2d w;
  for (int k = 0; k < 2; ++k) {
    const PointResult p = strained_centre(body, strains[k]);
    a(k, 0) = p.w1 / 2;
    a(k, 1) = dimension == 2 ? p.w2 / 3 : p.w3 / 4;
    w(k) = continuum_energy(strains[k], moduli);
  }
  // Regular when the family has sets of the higher order (N2 or N3 > 0); a relative
  // determinant guards against anything near singular rather than returning huge constants.
  const double det = a.determinant();
  if (!(std::abs(det) > 1e-8 * a.row(0).norm() * a.row(1).norm())) {
    throw std::invalid_argument(
        "calibrated constants need two- (2D) or three-neighbour (3D) sets, and at m = " +
        std::to_string(m) + " an interior lattice point has " +
        (dimension == 2 ? "N2 = " + std::to_string(body.n2[0])
                        : "N3 = " + std::to_string(body.n3[0])) +
        ": the bulk and uniaxial responses cannot both be matched (use m >= 1.5)");
  }
  const Eigen::Vector2d k = a.partialPivLu().solve(w);
  // Back to spacing dx: W1 scales like C1 dx^(d+1), W2 like C2 dx^6 (2D), W3 like C3 dx^12.
  InteractionConstants c;
  c.c1 = k(0) / std::pow(spacing, dimension + 1);
  if (dimension == 2)
    c.c2 = k(1) / std::pow(spacing, 6);
  else
    c.c3 = k(1) / std::pow(spacing, 12);
  return c;
}

}  // namespace ckpd
