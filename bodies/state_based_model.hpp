#pragma once
// The nonlinear ordinary state-based solid of seed 002 (Tupek, "Ordinary peridynamic materials
// based on nonlinear bond-strain measures"; THEORY.md section "The state-based solid"). Bonds
// only, but every bond feels the whole family through the weighted dilatation
//   theta_i = tr_w(phi eps) = sum_j w_ij phi_ij eps_ij V_j,
// with the Seth-Hill bond strain eps = (c^m - 1) / (2m) (m = 0: log(c) / 2), c = |Y|^2 / |xi|^2,
// and the energy density
//   psi_i = lambda_bar theta_i^2 / 2 + mu_bar sum_j w_ij phi_ij eps_ij^2 V_j.
// The force density on i is sum_j V_j (t_ij + t_ji) Y_ij with the scalar bond force
//   t_ij = phi [lambda_bar theta_i + 2 mu_bar eps_ij] w c^(m-1) / |xi|^2,
// the exact gradient of sum_i V_i psi_i. It is a two-pass kernel: theta over every family, then
// the bond forces. The weight is w(r) = C_d (3r + delta)(delta - r)^3, C_2 = 10 / (pi delta^6),
// C_3 = 315 / (16 pi delta^7) (tr_w(1) = d in the continuum), times one body-wide factor that
// makes tr_w(1) = d exactly for the fullest family of the discretisation
// (StateBasedConstants::weight_scale). A bond fails, for good, when eps >= 0 and the mean of its
// two ends' instantaneous bond energies lambda_bar eps theta + mu_bar eps^2 reaches
// beta / |xi|^2 (beta = pi delta Gc / 16 in 2D, 16 delta Gc / 63 in 3D).
//
// Every loop is a plain loop over points in index order (OpenMP static schedule), each point
// writing only its own entries, and every sum a fixed-order sum: results do not depend on the
// number of threads.
#include <Eigen/Core>
#include <vector>

#include "bodies/body.hpp"

namespace ckpd {

// The model's table (force_model.hpp), `model: state_based`.
const ForceModelKernels& state_based_kernels();

// The continuum-normalised weight w(r) of a d-dimensional body (0 for r >= delta).
double state_based_weight(int dimension, double r, double horizon);
// beta of the critical bond energy beta / |xi|^2 that dissipates Gc per unit crack area (length
// in 2D) with the continuum-normalised weight.
double state_based_failure_beta(int dimension, double horizon, double fracture_energy);
// lambda_bar, mu_bar matching the continuum Lame constants lambda, mu at small uniform strain
// (2D: lambda_bar = lambda - mu, mu_bar = 2 mu; 3D: lambda_bar = lambda - mu, mu_bar = 5 mu / 2).
StateBasedConstants state_based_constants(int dimension, double lambda, double mu);

// theta_i at the current displacement, every point (the first pass).
void state_based_dilatation(const Body& body, std::vector<double>& theta);
// psi_i at the current displacement, every point.
void state_based_energy_density(const Body& body, std::vector<double>& psi);
// The Kirchhoff stress of point i's own energy (THEORY.md section 9), the virial
//   tau_i = sum_j d psi_i / d Y_ij (x) Y_ij
//         = sum_j phi [lambda_bar theta_i + 2 mu_bar eps_ij] w V_j c^(m-1) / |xi|^2 Y (x) Y.
Eigen::Matrix3d state_based_point_kirchhoff_stress(const Body& body, std::size_t i);
// The free-surface parameter D_i = 1 - tr_w(phi) / d (0 inside a full, intact family). A body of
// another model is weighted as a state-based one would be, normalised by its fullest family:
// `whole`'s, when `body` is a part of it (a rank's points and halo), else its own.
void state_based_free_surface(const Body& body, std::vector<double>& D,
                              const Body* whole = nullptr);
// The stiffness bound k_i (Body::stiffness_bound) of the tangent at the current displacement
// (at the reference state for u = 0): a directional Gershgorin bound of every term's Hessian.
void state_based_stiffness_bound(const Body& body, std::vector<double>& bound);

}  // namespace ckpd
