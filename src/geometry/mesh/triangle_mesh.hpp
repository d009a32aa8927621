#pragma once
// A triangle surface: vertex positions and triangles as index triples, wound counter-clockwise
// seen from outside (the right-hand normal points out). Bodies are sampled inside such surfaces
// and mesh walls are made of them.
#include <array>
#include <cstdint>
#include <vector>

#include "bodies/vec.hpp"

namespace ckpd {

struct TriangleMesh {
  std::vector<Vec3> vertex;
  std::vector<std::array<std::uint32_t, 3>> triangle;

  const Vec3& corner(std::size_t t, int k) const { return vertex[triangle[t][k]]; }
  // (b - a) x (c - a): twice the area along the outward normal.
  Vec3 area_normal(std::size_t t) const {
    return (corner(t, 1) - corner(t, 0)).cross(corner(t, 2) - corner(t, 0));
  }
  // Axis-aligned box of the vertices.
  void bounds(Vec3& lo, Vec3& hi) const;
};

}  // namespace ckpd
