#pragma once
// Shared by the kernel tests: lattice blocks (optionally jittered into clouds) away from the
// origin, random displacements and bond failures, and the comparison of the fast kernel against
// the reference kernel compute_internal_force at given OpenMP thread counts.
#include <omp.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "bodies/body.hpp"
#include "bodies/material.hpp"
#include "bodies/symmetric_kernel.hpp"
#include "reference/internal_force.hpp"

namespace kernel_comparison {

using ckpd::Body;
using ckpd::BodyDefinition;
using ckpd::InteractionConstants;
using ckpd::PlaneMode;
using ckpd::Vec3;

constexpr double kDx = 1e-3;
constexpr double kM = 3.015;
constexpr double kE = 210e9;

// Restores the OpenMP thread count when a test ends, whatever it set.
class ThreadCountGuard {
 public:
  ThreadCountGuard() : saved_(omp_get_max_threads()) {}
  ~ThreadCountGuard() { omp_set_num_threads(saved_); }

 private:
  int saved_;
};

// nx x ny x nz lattice (nz = 1 in 2D), away from the origin so that offsets carry rounding,
// optionally jittered by up to +-jitter dx per in-plane component.
inline BodyDefinition block(int dimension, int nx, int ny, int nz, InteractionConstants constants,
                            double jitter, std::mt19937& rng, double m = kM) {
  BodyDefinition d;
  d.name = "block";
  d.dimension = dimension;
  d.density = 7850;
  d.horizon = m * kDx;
  d.constants = constants;
  d.critical_stretch = 1.0;  // finite: damage on (failed bonds count), but nothing fails here
  std::uniform_real_distribution<double> u(-jitter * kDx, jitter * kDx);
  const Vec3 origin(0.37, -0.21, dimension == 3 ? 0.113 : 0.0);
  for (int z = 0; z < (dimension == 3 ? nz : 1); ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        Vec3 p = origin + kDx * Vec3(x, y, z);
        if (jitter > 0)
          for (int c = 0; c < dimension; ++c) p[c] += u(rng);
        d.reference_position.push_back(p);
      }
  const double cell = dimension == 3 ? kDx * kDx * kDx : kDx * kDx;
  d.volume.assign(d.reference_position.size(), cell);
  // The largest family volume that occurs, so that beta <= 1 everywhere.
  const ckpd::BondFamily family = ckpd::build_bond_family(d.reference_position, d.horizon);
  std::size_t largest = 0;
  for (std::size_t i = 0; i < family.points(); ++i)
    largest = std::max(largest, family.family_size(i));
  d.full_family_volume = static_cast<double>(largest) * cell;
  return d;
}

// Point volumes scaled by random factors in [0.7, 1.3] (the family volume raised with them, so
// beta stays <= 1): where the vertices of a set carry different volumes the energy-consistent
// form differs from the own-family one, and tests of it need such bodies.
inline void vary_volumes(BodyDefinition& d, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.7, 1.3);
  for (double& v : d.volume) v *= u(rng);
  d.full_family_volume *= 1.3;
}

// Random displacements of up to +-amplitude dx per component (in-plane in 2D).
inline void perturb(Body& body, double amplitude, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-amplitude * kDx, amplitude * kDx);
  for (Vec3& d : body.displacement) {
    d = Vec3(u(rng), u(rng), body.dimension == 3 ? u(rng) : 0.0);
  }
}

// Fails each bond with probability `fraction`, both stored directions together.
inline void fail_bonds(Body& body, double fraction, std::mt19937& rng) {
  std::bernoulli_distribution fail(fraction);
  const auto& f = body.family;
  for (std::size_t i = 0; i < body.size(); ++i) {
    for (std::size_t k = f.offset[i]; k < f.offset[i + 1]; ++k) {
      const std::uint32_t j = f.neighbour[k];
      if (j < i || !fail(rng)) continue;
      body.bond_intact[k] = 0;
      const auto row_begin = f.neighbour.begin() + static_cast<std::ptrdiff_t>(f.offset[j]);
      const auto row_end = f.neighbour.begin() + static_cast<std::ptrdiff_t>(f.offset[j + 1]);
      const auto back = std::lower_bound(row_begin, row_end, static_cast<std::uint32_t>(i));
      REQUIRE((back != row_end && *back == i));
      body.bond_intact[static_cast<std::size_t>(back - f.neighbour.begin())] = 0;
    }
  }
}

inline double max_norm(const std::vector<Vec3>& v) {
  double m = 0;
  for (const Vec3& x : v) m = std::max(m, x.norm());
  return m;
}

inline double max_abs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

struct Difference {
  double force = 0, energy = 0;  // max difference over the largest reference value
};

// The reference once, then the fast kernel with each thread count; relative differences.
inline std::vector<Difference> compare_kernels(Body& body, const std::vector<int>& thread_counts) {
  ckpd::compute_internal_force(body, true);
  const std::vector<Vec3> force = body.force_density;
  const std::vector<double> energy = body.strain_energy_density;
  const double fscale = max_norm(force), escale = max_abs(energy);
  REQUIRE(fscale > 0);
  REQUIRE(escale > 0);
  std::vector<Difference> result;
  for (const int threads : thread_counts) {
    for (auto& f : body.force_density) f = Vec3::Constant(1e300);  // must be overwritten
    for (auto& e : body.strain_energy_density) e = 1e300;
    omp_set_num_threads(threads);
    ckpd::compute_internal_force_symmetric(body, true);
    Difference d;
    for (std::size_t i = 0; i < body.size(); ++i) {
      d.force = std::max(d.force, (body.force_density[i] - force[i]).norm());
      d.energy = std::max(d.energy, std::abs(body.strain_energy_density[i] - energy[i]));
    }
    d.force /= fscale;
    d.energy /= escale;
    result.push_back(d);
  }
  return result;
}

inline Difference compare_kernels(Body& body, int threads) {
  return compare_kernels(body, std::vector<int>{threads})[0];
}

struct Scene {
  std::string label;
  int dimension;
  double nu;
  double jitter;
  int nx, ny, nz;
  bool triangles_in_3d = false;  // C2 != 0 in 3D: not a physical setting, but allowed
  double m = kM;                 // horizon / spacing
};

inline InteractionConstants constants_for(const Scene& s) {
  if (s.triangles_in_3d) {
    InteractionConstants c = ckpd::interaction_constants(3, kE, s.nu, PlaneMode::none, s.m * kDx);
    c.c2 = c.c3 * std::pow(s.m * kDx, 3);  // comparable in size to the tetrahedron terms
    return c;
  }
  return ckpd::interaction_constants(
      s.dimension, kE, s.nu, s.dimension == 2 ? PlaneMode::stress : PlaneMode::none, s.m * kDx);
}

}  // namespace kernel_comparison
