#pragma once
// Where a line parallel to a coordinate axis crosses a triangle surface. The triangles are binned
// over the plane normal to the axis, so a line meets only the few in its cell.
//
// Watertight by construction: whether a line passes inside a triangle is decided by the signs
// of its three edge functions, and each edge function is evaluated from the edge's vertices in
// index order, so the two triangles that share an edge see the same number with opposite signs.
// A line exactly through an edge or a vertex is moved by a symbolic perturbation (eps, eps^2)
// in the plane, which puts it strictly inside exactly one triangle of a closed fan. Hence on a
// closed, consistently wound surface the signed crossings of every line add up to zero, and the
// answer does not depend on the order of the triangles (or of the file they came from).
#include <cstdint>
#include <vector>

#include "src/geometry/mesh/triangle_mesh.hpp"

namespace ckpd {

struct AxisCrossing {
  double at = 0;  // coordinate along the axis
  int sign = 0;   // +1 where the surface's outward normal has a positive axis component
  bool operator<(const AxisCrossing& o) const { return at != o.at ? at < o.at : sign < o.sign; }
};

class AxisRays {
 public:
  // `mesh` must outlive this object.
  AxisRays(const TriangleMesh& mesh, int axis);

  int axis() const { return axis_; }
  // The crossings of the line through (u, v) (the coordinates along axes axis+1 and axis+2,
  // cyclically), sorted. `out` is overwritten.
  void crossings(double u, double v, std::vector<AxisCrossing>& out) const;

 private:
  std::size_t cell(double u, double v) const;
  int cell_u(double u) const;
  int cell_v(double v) const;

  const TriangleMesh& mesh_;
  int axis_, iu_, iv_;
  double u0_ = 0, v0_ = 0, hu_ = 1, hv_ = 1;
  int nu_ = 1, nv_ = 1;
  std::vector<std::uint32_t> offset_;    // CSR over cells
  std::vector<std::uint32_t> triangle_;  // triangle indices, sorted within each cell
};

}  // namespace ckpd
