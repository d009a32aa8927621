#include "src/geometry/mesh/mesh_properties.hpp"

namespace ckpd {

namespace {

// Eberly's subexpressions of one coordinate over a triangle's three corners.
struct Sub {
  double f1, f2, f3, g0, g1, g2;
};

Sub subexpressions(double w0, double w1, double w2) {
  const double temp0 = w0 + w1, temp1 = w0 * w0, temp2 = temp1 + w1 * temp0;
  Sub s;
  s.f1 = temp0 + w2;
  s.f2 = temp2 + w2 * s.f1;
  s.f3 = w0 * temp1 + w1 * temp2 + w2 * s.f2;
  s.g0 = s.f2 + w0 * (s.f1 + w0);
  s.g1 = s.f2 + w1 * (s.f1 + w1);
  s.g2 = s.f2 + w2 * (s.f1 + w2);
  return s;
}

}  // namespace

MeshMassProperties mesh_mass_properties(const TriangleMesh& mesh) {
  // Integrals of 1, x, y, z, x^2, y^2, z^2, xy, yz, zx over the solid. Taken about the box
  // centre, so that a body far from the origin loses no digits.
  Vec3 lo, hi;
  mesh.bounds(lo, hi);
  const Vec3 origin = 0.5 * (lo + hi);
  double in[10] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  for (std::size_t t = 0; t < mesh.triangle.size(); ++t) {
    const Vec3 p0 = mesh.corner(t, 0) - origin, p1 = mesh.corner(t, 1) - origin,
               p2 = mesh.corner(t, 2) - origin;
    const Vec3 d = (p1 - p0).cross(p2 - p0);
    const Sub x = subexpressions(p0.x(), p1.x(), p2.x());
    const Sub y = subexpressions(p0.y(), p1.y(), p2.y());
    const Sub z = subexpressions(p0.z(), p1.z(), p2.z());
    in[0] += d.x() * x.f1;
    in[1] += d.x() * x.f2;
    in[2] += d.y() * y.f2;
    in[3] += d.z() * z.f2;
    in[4] += d.x() * x.f3;
    in[5] += d.y() * y.f3;
    in[6] += d.z() * z.f3;
    in[7] += d.x() * (p0.y() * x.g0 + p1.y() * x.g1 + p2.y() * x.g2);
    in[8] += d.y() * (p0.z() * y.g0 + p1.z() * y.g1 + p2.z() * y.g2);
    in[9] += d.z() * (p0.x() * z.g0 + p1.x() * z.g1 + p2.x() * z.g2);
  }
  in[0] /= 6;
  for (int k = 1; k <= 3; ++k) in[k] /= 24;
  for (int k = 4; k <= 6; ++k) in[k] /= 60;
  for (int k = 7; k <= 9; ++k) in[k] /= 120;
  MeshMassProperties m;
  m.volume = in[0];
  if (m.volume == 0) return m;
  const Vec3 c(in[1] / m.volume, in[2] / m.volume, in[3] / m.volume);
  m.centroid = c + origin;
  const double V = m.volume;
  Eigen::Matrix3d& I = m.second_moment;
  I(0, 0) = in[5] + in[6] - V * (c.y() * c.y() + c.z() * c.z());
  I(1, 1) = in[4] + in[6] - V * (c.z() * c.z() + c.x() * c.x());
  I(2, 2) = in[4] + in[5] - V * (c.x() * c.x() + c.y() * c.y());
  I(0, 1) = I(1, 0) = -(in[7] - V * c.x() * c.y());
  I(1, 2) = I(2, 1) = -(in[8] - V * c.y() * c.z());
  I(0, 2) = I(2, 0) = -(in[9] - V * c.z() * c.x());
  return m;
}

}  // namespace ckpd
