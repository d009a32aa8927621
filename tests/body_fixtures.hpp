#pragma once
// Small bodies for the unit tests: lattice blocks, jittered clouds, random displacements and
// random (symmetric) bond failures. Deterministic: every random helper takes its generator.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "bodies/body.hpp"
#include "bodies/bond_family.hpp"

namespace ckpd_test {

using ckpd::Vec3;

// Number of nonzero offsets of the unit (square or cubic) lattice within radius m.
inline int lattice_offsets_within(int dimension, double m) {
  const int h = static_cast<int>(std::ceil(m));
  const int zr = dimension == 3 ? h : 0;
  int count = 0;
  for (int z = -zr; z <= zr; ++z)
    for (int y = -h; y <= h; ++y)
      for (int x = -h; x <= h; ++x) {
        if (x == 0 && y == 0 && z == 0) continue;
        if (std::sqrt(double(x * x + y * y + z * z)) <= m * (1 + 1e-12)) ++count;
      }
  return count;
}

// A block of nx x ny x nz lattice points (nz = 1 in 2D) with spacing dx and horizon m dx.
inline ckpd::BodyDefinition lattice_block(int dimension, int nx, int ny, int nz, double dx,
                                          double m, ckpd::InteractionConstants constants,
                                          double density = 1.0) {
  ckpd::BodyDefinition d;
  d.name = "block";
  d.dimension = dimension;
  d.density = density;
  d.horizon = m * dx;
  d.constants = constants;
  const int layers = dimension == 3 ? nz : 1;
  for (int z = 0; z < layers; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) d.reference_position.emplace_back(x * dx, y * dx, z * dx);
  const double cell = dimension == 3 ? dx * dx * dx : dx * dx;
  d.volume.assign(d.reference_position.size(), cell);
  d.full_family_volume = lattice_offsets_within(dimension, m) * cell;
  return d;
}

// The lattice block with every point moved by up to +-jitter dx in each in-plane direction;
// the full family volume is the largest family volume that occurs, so beta <= 1.
inline ckpd::BodyDefinition jittered_cloud(int dimension, int nx, int ny, int nz, double dx,
                                           double m, ckpd::InteractionConstants constants,
                                           double jitter, std::mt19937& rng) {
  ckpd::BodyDefinition d = lattice_block(dimension, nx, ny, nz, dx, m, constants);
  std::uniform_real_distribution<double> u(-jitter * dx, jitter * dx);
  for (Vec3& p : d.reference_position) {
    for (int c = 0; c < dimension; ++c) p[c] += u(rng);
  }
  const ckpd::BondFamily f = ckpd::build_bond_family(d.reference_position, d.horizon);
  double largest = 0;
  for (std::size_t i = 0; i < f.points(); ++i) {
    double v = 0;
    for (std::size_t k = f.offset[i]; k < f.offset[i + 1]; ++k) v += d.volume[f.neighbour[k]];
    largest = std::max(largest, v);
  }
  d.full_family_volume = largest;
  return d;
}

// Random displacement of up to +-amplitude in each in-plane direction.
inline void perturb(ckpd::Body& body, double amplitude, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  for (Vec3& d : body.displacement) {
    d.setZero();
    for (int c = 0; c < body.dimension; ++c) d[c] = u(rng);
  }
}

// The CSR slot of bond i -> j, or -1.
inline std::ptrdiff_t bond_slot(const ckpd::Body& body, std::size_t i, std::size_t j) {
  const auto begin = body.family.neighbour.begin() + body.family.offset[i];
  const auto end = body.family.neighbour.begin() + body.family.offset[i + 1];
  const auto it = std::lower_bound(begin, end, static_cast<std::uint32_t>(j));
  if (it == end || *it != j) return -1;
  return it - body.family.neighbour.begin();
}

// Fails bond i-j in both stored directions.
inline void fail_bond(ckpd::Body& body, std::size_t i, std::size_t j) {
  body.bond_intact[static_cast<std::size_t>(bond_slot(body, i, j))] = 0;
  body.bond_intact[static_cast<std::size_t>(bond_slot(body, j, i))] = 0;
}

// Fails each bond (both directions) with the given probability; returns the number failed.
inline std::size_t fail_random_bonds(ckpd::Body& body, double probability, std::mt19937& rng) {
  std::bernoulli_distribution pick(probability);
  std::size_t failed = 0;
  for (std::size_t i = 0; i < body.size(); ++i) {
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k) {
      const std::size_t j = body.family.neighbour[k];
      if (j > i && pick(rng)) {
        fail_bond(body, i, j);
        ++failed;
      }
    }
  }
  return failed;
}

}  // namespace ckpd_test
