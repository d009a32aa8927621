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
  // Current offsets to a and b, and the cross products of the reference and current offsets
  // (computed by cross() where a set evaluated with the pair needs them): the triangle's area
  // vector and, for tetrahedra, the gradient of v at the fourth vertex.
  double pa[3], pb[3], RPQ[3], pq[3];
  bool crossed = false;
  // Row a of the adjacency and of the intact adjacency.
  const std::uint64_t* ra = nullptr;
  const std::uint64_t* ia = nullptr;
  // Far-field masking: i, a and b are all linear, so the triangle is left out and only the
  // tetrahedra whose fourth vertex is in this row (the exact slots) are evaluated; null: all.
  const std::uint64_t* only = nullptr;

  // P x Q and p x q of slots a and b (once per pair).
  void cross(const SymmetricKernelThread& t) {
    if (crossed) return;
    const double Pa[3] = {t.Rx[a], t.Ry[a], t.Rz[a]};
    const double Pb[3] = {t.Rx[b], t.Ry[b], t.Rz[b]};
    RPQ[0] = Pa[1] * Pb[2] - Pa[2] * Pb[1];
    RPQ[1] = Pa[2] * Pb[0] - Pa[0] * Pb[2];
    RPQ[2] = Pa[0] * Pb[1] - Pa[1] * Pb[0];
    pq[0] = pa[1] * pb[2] - pa[2] * pb[1];
    pq[1] = pa[2] * pb[0] - pa[0] * pb[2];
    pq[2] = pa[0] * pb[1] - pa[1] * pb[0];
    crossed = true;
  }
};

}  // namespace ckpd::symmetric
