#pragma once
// Samples a shape on a regular lattice (cubic in 3D, square in 2D) of spacing dx: points at the
// lattice sites inside the shape, each with the cell volume dx^d. The lattice is centred on the
// shape's bounding box, so a box whose edges are multiples of dx is filled cell-centred and a
// sphere is sampled symmetrically.
#include <cstddef>
#include <vector>

#include "bodies/vec.hpp"
#include "src/geometry/shape.hpp"

namespace ckpd {

struct LatticeSample {
  std::vector<Vec3> position;
  std::vector<double> volume;
  double full_family_volume = 0;  // lattice offsets within the horizon times the cell volume
};

// Throws std::invalid_argument for an unbounded shape, or when the bounding box would hold more
// than `max_points` lattice sites (the message gives the estimate).
LatticeSample sample_lattice(const Shape& shape, int dimension, double spacing, double horizon,
                             std::size_t max_points);

// Number of lattice offsets (not the origin) within `horizon` on a lattice of spacing `spacing`.
std::size_t lattice_family_size(int dimension, double spacing, double horizon);

}  // namespace ckpd
