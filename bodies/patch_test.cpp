#include "bodies/patch_test.hpp"

#include <cmath>
#include <stdexcept>

#include "bodies/body.hpp"
#include "bodies/internal_force.hpp"

namespace ckpd {

namespace {

BodyDefinition lattice_block(int dimension, double m, InteractionConstants constants) {
  const int h = static_cast<int>(std::ceil(m)) + 1;
  BodyDefinition d;
  d.name = "patch";
  d.dimension = dimension;
  d.density = 1;
  d.horizon = m;
  d.constants = constants;
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

double energy_ratio(const Body& body, const Eigen::Matrix3d& e, const ElasticModuli& moduli) {
  Body b = body;
  for (std::size_t i = 0; i < b.size(); ++i) b.displacement[i] = e * b.reference_position[i];
  FamilyScratch scratch;
  const double w = evaluate_point(b, 0, scratch).strain_energy_density();
  const double continuum =
      0.5 * moduli.lambda * e.trace() * e.trace() + moduli.mu * (e.array() * e.array()).sum();
  return w / continuum;
}

}  // namespace

PatchTestResult run_patch_test(int dimension, double m, double E, double nu, PlaneMode plane,
                               double eps) {
  if (!(m >= 1)) throw std::invalid_argument("horizon ratio m must be at least 1");
  const ElasticModuli moduli = elastic_moduli(dimension, E, nu, plane);
  const InteractionConstants c = interaction_constants(dimension, E, nu, plane, m);

  PatchTestResult r;
  {  // Count every family, whatever the constants.
    InteractionConstants counting{1, 1, dimension == 3 ? 1.0 : 0.0};
    const Body counter = make_body(lattice_block(dimension, m, counting));
    r.n1 = static_cast<std::uint32_t>(counter.family.family_size(0));
    r.n2 = counter.n2[0];
    r.n3 = counter.n3[0];
  }
  const Body body = make_body(lattice_block(dimension, m, c));
  Eigen::Matrix3d e = Eigen::Matrix3d::Zero();
  for (int d = 0; d < dimension; ++d) e(d, d) = eps;
  r.volumetric = energy_ratio(body, e, moduli);
  e.setZero();
  e(0, 1) = e(1, 0) = eps;
  r.shear = energy_ratio(body, e, moduli);
  e.setZero();
  e(0, 0) = eps;
  r.uniaxial = energy_ratio(body, e, moduli);
  return r;
}

}  // namespace ckpd
