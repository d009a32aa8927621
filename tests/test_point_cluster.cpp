// The cluster that takes up a frictional couple at a deformable point (contact/point_cluster.hpp)
// on raw arrays: its forces sum to zero and their torque is the couple (3D, 2D), the spin of a
// rigidly turning cluster is its angular velocity, the forces' power is the couple times the
// spin, and broken bonds leave the cluster (a collinear rest takes no couple about its line).
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

#include "contact/point_cluster.hpp"

using namespace ckpd;

namespace {

constexpr double kDensity = 7850, kSpacing = 1e-3;

// A jittered lattice neighbourhood of point 0 (at `centre`) with varying volumes; every other
// point is bonded to point 0, families stored as the bodies store them (CSR, both ends).
struct Neighbourhood {
  std::vector<Vec3> reference, displacement, velocity, force;
  std::vector<double> volume;
  std::vector<std::size_t> offset;
  std::vector<std::uint32_t> neighbour;
  std::vector<std::uint8_t> intact;
  int dimension;

  Neighbourhood(int dim, const Vec3& centre, std::mt19937& rng) : dimension(dim) {
    std::uniform_real_distribution<double> u(-0.2, 0.2);
    reference.push_back(centre);
    for (int i = -1; i <= 1; ++i)
      for (int j = -1; j <= 1; ++j)
        for (int k = (dim == 3 ? -1 : 0); k <= (dim == 3 ? 1 : 0); ++k) {
          if (i == 0 && j == 0 && k == 0) continue;
          // Off-centre: a surface point's family lies on one side (i >= 0 kept only).
          if (i < 0) continue;
          reference.push_back(centre +
                              kSpacing * Vec3(i + u(rng), j + u(rng), dim == 3 ? k + u(rng) : 0.0));
        }
    const std::size_t n = reference.size();
    for (std::size_t p = 0; p < n; ++p) {
      displacement.emplace_back(1e-5 * u(rng), 1e-5 * u(rng), dim == 3 ? 1e-5 * u(rng) : 0.0);
      velocity.emplace_back(30 + u(rng), -20 + u(rng), dim == 3 ? 5 + u(rng) : 0.0);
      volume.push_back(kSpacing * kSpacing * (dim == 3 ? kSpacing : 1.0) * (1 + u(rng)));
    }
    force.assign(n, Vec3::Zero());
    // Point 0 bonded to all; the others to point 0 only.
    offset.push_back(0);
    for (std::uint32_t p = 1; p < n; ++p) neighbour.push_back(p);
    offset.push_back(neighbour.size());
    for (std::size_t p = 1; p < n; ++p) {
      neighbour.push_back(0);
      offset.push_back(neighbour.size());
    }
    intact.assign(neighbour.size(), 1);
  }

  PointSet view() {
    PointSet p;
    p.name = "cluster";
    p.dimension = dimension;
    p.density = kDensity;
    p.reference = reference;
    p.displacement = displacement;
    p.velocity = velocity;
    p.volume = volume;
    p.force_density = force;
    p.family_offset = offset;
    p.family_neighbour = neighbour;
    p.bond_intact = intact;
    return p;
  }

  Vec3 x(std::size_t i) const { return reference[i] + displacement[i]; }
  double mass(std::size_t i) const { return kDensity * volume[i]; }
};

struct Resultant {
  Vec3 force = Vec3::Zero(), torque = Vec3::Zero();  // torque about the origin
  double power = 0, scale = 0;                       // scale: sum |g_k|
};

Resultant resultant(const Neighbourhood& h) {
  Resultant r;
  for (std::size_t k = 0; k < h.reference.size(); ++k) {
    const Vec3 g = h.volume[k] * h.force[k];
    r.force += g;
    r.torque += h.x(k).cross(g);
    r.power += g.dot(h.velocity[k]);
    r.scale += g.norm();
  }
  return r;
}

}  // namespace

TEST_CASE("a cluster takes up a couple with forces of zero sum whose torque is the couple") {
  std::mt19937 rng(7);
  for (int dim : {3, 2}) {
    Neighbourhood h(dim, Vec3(0.31, -0.12, dim == 3 ? 0.05 : 0.0), rng);
    const Vec3 torque = dim == 3 ? Vec3(0.7, -1.3, 0.4) : Vec3(0, 0, -1.1);  // N m
    const PointSet view = h.view();
    add_cluster_couple(view, 0, torque);
    const Resultant r = resultant(h);
    INFO("dimension " << dim);
    REQUIRE(r.scale > 0);
    CHECK(r.force.norm() < 1e-14 * r.scale);
    // Zero sum: the torque is the same about any point, here about the origin, 0.3 m away.
    CHECK((r.torque - torque).norm() < 1e-12 * torque.norm());
    // The power of the forces is the couple times the cluster's spin (J^+ symmetric).
    const Vec3 spin = cluster_spin(view, 0);
    CHECK(std::abs(r.power - torque.dot(spin)) < 1e-12 * r.scale * h.velocity[0].norm());
    if (dim == 2)
      for (const Vec3& f : h.force) CHECK(f.z() == 0);
  }
}

TEST_CASE("the spin of a rigidly turning cluster is its angular velocity") {
  std::mt19937 rng(11);
  for (int dim : {3, 2}) {
    Neighbourhood h(dim, Vec3(-0.2, 0.4, 0.0), rng);
    const Vec3 omega = dim == 3 ? Vec3(120, -40, 75) : Vec3(0, 0, 310);  // rad/s
    const Vec3 v0(12, -7, dim == 3 ? 3 : 0);
    for (std::size_t k = 0; k < h.reference.size(); ++k)
      h.velocity[k] = v0 + omega.cross(h.x(k) - h.x(0));
    const Vec3 spin = cluster_spin(h.view(), 0);
    INFO("dimension " << dim << ": spin " << spin.transpose());
    CHECK((spin - omega).norm() < 1e-10 * omega.norm());
  }
}

TEST_CASE("broken bonds leave the cluster; a collinear one takes no couple about its line") {
  std::mt19937 rng(3);
  Neighbourhood h(3, Vec3(0, 0, 0), rng);
  // Point 0 keeps one bond: a cluster of two points, no couple about their line.
  std::fill(h.intact.begin(), h.intact.end(), 0);
  h.intact[0] = 1;  // 0 -> 1
  const Vec3 line = (h.x(1) - h.x(0)).normalized();
  const Vec3 across = line.cross(Vec3(0.3, 0.8, -0.5)).normalized();
  add_cluster_couple(h.view(), 0, 2.0 * line + 3.0 * across);
  const Resultant r = resultant(h);
  for (std::size_t k = 2; k < h.force.size(); ++k) CHECK(h.force[k] == Vec3::Zero());
  CHECK(r.force.norm() < 1e-14 * r.scale);
  // Of the couple only the part across the line is applied.
  CHECK((r.torque - 3.0 * across).norm() < 1e-12 * 3.0);
  // Without any intact bond nothing is applied and the spin is zero.
  std::fill(h.intact.begin(), h.intact.end(), 0);
  std::fill(h.force.begin(), h.force.end(), Vec3::Zero());
  add_cluster_couple(h.view(), 0, across);
  for (const Vec3& f : h.force) CHECK(f == Vec3::Zero());
  CHECK(cluster_spin(h.view(), 0) == Vec3::Zero());
}
