#pragma once
// Per-point stress from the CKPD energy (THEORY.md section 9), for output only: a separate pass
// over a point's own family, never called by the force kernels.
//
// Point i owns the energy V^i W^i, W^i = W1/2 + W2/3 + W3/4 (its share of every set of its
// family). Each set S of i's family is a function of the positions of its vertices c (i is
// vertex 0); translation invariance lets its virial be written with offsets from x^i:
//   tau^i = (1/V^i) sum_S sum_c d(V^i W^i_S)/dx^c (x) (x^c - x^i)
//         = -sum_S (1/(n_S + 1)) sum_c k_S f^S_c (x) (x^c - x^i),
// f^S_c the set's vertex forces per unit force weight k_S (ckpd_model.hpp: bond_term,
// triangle_term, tetrahedron_term), n_S + 1 the number of its vertices. Under a homogeneous
// deformation x = F X this is dW^i/dF F^T, the Kirchhoff stress J sigma of the point's energy
// (J = det F): the Cauchy stress is tau^i / J^i. Summed over the points,
//   sum_i V^i tau^i = sum_k dE/dx^k (x) x^k,   E = sum_i V^i W^i,
// the virial of the body's total strain energy (the global virial stress times the current
// volume). Failed bonds and the sets they switch off contribute nothing, as in the kernels.
#include <Eigen/Core>
#include <cstddef>

#include "bodies/body.hpp"
#include "bodies/family_scratch.hpp"

namespace ckpd {

// tau^i (symmetric for rotation-invariant energies; returned as computed). A body without
// families (rigid) or a model without vertex-force functions throws std::invalid_argument.
Eigen::Matrix3d point_kirchhoff_stress(const Body& body, std::size_t i, FamilyScratch& scratch);

// tau^i of every point (OpenMP over points).
void kirchhoff_stress(const Body& body, std::vector<Eigen::Matrix3d>& out);

}  // namespace ckpd
