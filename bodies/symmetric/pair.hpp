#pragma once
// One pair (a, b) of point i's upper family, bonded to each other: the edge pair of a triangle
// {i, a, b} and of the tetrahedra {i, a, b, c} built on it.
#include "bodies/symmetric/centre.hpp"

namespace ckpd::symmetric {

struct Pair {
  std::size_t a = 0, b = 0;
  std::size_t number = 0;  // stencil path: the pair's index in the stencil's tables
  // Which vertices have both (all) of their bonds in the set intact (d2, d3); under all_edges,
  // every vertex needs all three edges of the triangle intact (edges_ab).
  bool act_i = false, act_j = false, act_k = false, edges_ab = false;
  // Reference and current offsets to a and b and their cross products: the triangle's area
  // vector and, for tetrahedra, the gradient of v at the fourth vertex. (The stencil path has
  // the pair's reference numbers in its tables and needs RPQ only on the general path.)
  double pa[3], pb[3], RPQ[3], pq[3];
  // Row a of the adjacency and of the intact adjacency.
  const std::uint64_t* ra = nullptr;
  const std::uint64_t* ia = nullptr;
  // Far-field masking: i, a and b are all linear, so the triangle is left out and only the
  // tetrahedra whose fourth vertex is in this row (the exact slots) are evaluated; null: all.
  const std::uint64_t* only = nullptr;
};

}  // namespace ckpd::symmetric
