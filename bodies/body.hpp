#pragma once
// One CKPD body: structure-of-arrays point data, its bond families, the per-point interaction
// counts and effective volumes (THEORY.md sections 1-4). Two- and three-neighbour sets are never
// stored: they are enumerated from the bond family whenever they are needed.
#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "bodies/bond_family.hpp"
#include "bodies/force_model.hpp"
#include "bodies/material.hpp"
#include "bodies/upper_bonds.hpp"
#include "bodies/upper_rows.hpp"
#include "bodies/vec.hpp"

namespace ckpd {

struct LatticeStencil;

// Below this fraction of the product of its edge lengths from the centre point, a triangle's
// area or a tetrahedron's volume counts as degenerate (THEORY.md section 1); a body may raise it
// (BodyDefinition::degenerate_fraction).
inline constexpr double kDegenerateFraction = 1e-10;

// Bonds whose reference segment crosses this surface start failed (THEORY.md section 4).
// Two corners: a segment in the z = 0 plane (2D bodies). Three or more: a planar convex polygon
// (3D bodies). A bond is cut when its end points lie strictly on opposite sides of the line or
// plane and the crossing point lies inside the segment or polygon (edges included).
struct Precrack {
  std::vector<Vec3> corners;
};

// Which failed bonds switch a two- or three-neighbour set off (THEORY.md section 4).
// centre_bonds (THEORY.md): for vertex c, a set is off when one of c's own bonds in it failed, so
// a triangle or tetrahedron can stay on for some vertices and be off for others; the damaged
// forces are then not the gradient of one energy. all_edges: a set is on for all its vertices
// while every edge (3 of a triangle, 6 of a tetrahedron) is intact and off for all of them
// otherwise; each set's energy is switched as a whole, so the damaged model stays conservative
// (the energy of a switched-off set is booked as dissipated), at the price of losing more sets
// per failed bond.
enum class DamageRule { centre_bonds, all_edges };
DamageRule damage_rule_from_string(const std::string& name);  // throws std::invalid_argument
std::string to_string(DamageRule rule);

// How the CKPD forces follow from the energy (THEORY.md section 2b, MODEL.md section 2b).
// own_family: the seed's law, each point differentiates its own family's energy with its own
// effective volumes; not the gradient of one energy where the vertices of a set carry different
// V dVn (surfaces, clouds) or where damage switches a set off for some vertices only.
// energy_consistent: b^i = -(1/V^i) dE/dx^i of E = sum_c V^c (W1^c/2 + W2^c/3 + W3^c/4): every
// set acts on all its vertices with the mean over its vertices (those whose family holds it and
// where it is active) of V^c dVn^c, divided by the receiving point's V^i.
enum class ForceForm { own_family, energy_consistent };
ForceForm force_form_from_string(const std::string& name);  // throws std::invalid_argument
std::string to_string(ForceForm form);

struct BodyDefinition {
  std::string name;
  int dimension = 3;
  std::vector<Vec3> reference_position;
  std::vector<double> volume;  // per point; an area in 2D
  double density = 0;          // kg/m^3 (3D), kg/m^2 (2D)
  double horizon = 0;
  InteractionConstants constants;
  // Bonds fail when their stretch exceeds this; +inf disables damage (no damage bookkeeping).
  double critical_stretch = std::numeric_limits<double>::infinity();
  // Sum of the point volumes that an interior point's family holds in this discretisation;
  // beta^i is the family's point volume over this (THEORY.md section 1). For a lattice it is the
  // number of lattice offsets within the horizon times the cell volume.
  double full_family_volume = 0;
  // A family volume above the full one is an error unless this is set; then beta is capped at
  // 1 there. Irregular point clouds need it: with locally varying spacing a point's family can
  // hold more volume than the lattice reference, although its neighbourhood is simply full.
  bool cap_beta = false;
  // Two- and three-neighbour sets whose |A| / (L L) or |V| / (L L L) seen from the centre is at
  // most this are degenerate: left out, not counted. Lattices need only the default (their
  // non-degenerate sets are far above it); a smoothly distorted lattice, such as a point cloud
  // along a curve, turns the lattice's collinear and coplanar sets into slivers whose stiffness
  // (~ 1/size) throttles the stable step, and a larger value leaves them out as the lattice does.
  double degenerate_fraction = kDegenerateFraction;
  // Inversion penalty factor F >= 0 (0: off). The CKPD energy uses |v| (|a|), so a tetrahedron
  // (a 2D body's triangle) whose current signed volume has the opposite sign of its reference
  // one resists no more than an upright one and is pushed on towards the mirror image. With F,
  // each inverted ordered set adds psi = 2 F |C3| |v| (2D: 2 F |C2| |a|) to its energy; F = 1
  // makes the energy that of the signed volume, C3 |V| (v/V - 1)^2 / 2, smooth through v = 0.
  // Needs the three-neighbour family in 3D (nu != 1/4), the two-neighbour one in 2D.
  double inversion_penalty = 0;
  std::vector<std::uint8_t> no_failure;  // empty, or one flag per point: its bonds never fail
  std::vector<Precrack> precracks;
  // Use the lattice stencil (lattice_stencil.hpp) when the points form one; off: always the
  // general kernel path (for comparisons).
  bool lattice_stencil = true;
  DamageRule damage_rule = DamageRule::centre_bonds;
  // The force model (force_model.hpp); null: CKPD. `constants` are its per-family constants.
  const ForceModelKernels* model = nullptr;
  // The CKPD model's Seth-Hill strain measure m (ckpd_model.hpp): 1/2 is e = l/L - 1 (the
  // default law); any other m, finite, selects the Seth-Hill CKPD kernels. CKPD only.
  double strain_measure = 0.5;
  // The state-based model's constants (state_based_model.hpp); unused by the other models.
  StateBasedConstants state_based;
  // The CKPD model's force form (ForceForm); energy_consistent selects the conservative CKPD
  // kernels. CKPD only (a model given in `model` must leave it at own_family).
  ForceForm force_form = ForceForm::own_family;
};

// The symmetric kernel's degeneracy screens (symmetric_kernel.hpp), fixed by the reference
// configuration: |A| > hi2 (|V| > hi3) is non-degenerate for every vertex, < lo2 (lo3)
// degenerate for every vertex, in between each vertex decides; above well2 (well3) a set is
// evaluated once with shared geometry, below each vertex evaluates its own term.
struct SetScreens {
  double hi2 = 0, lo2 = 0, hi3 = 0, lo3 = 0, well2 = 0, well3 = 0;
};

struct Body {
  // Identity and material.
  std::string name;
  int dimension = 3;
  double density = 0;
  double horizon = 0;
  InteractionConstants constants;
  double critical_stretch = std::numeric_limits<double>::infinity();
  bool damage_enabled = false;
  double degenerate_fraction = kDegenerateFraction;   // BodyDefinition::degenerate_fraction
  double inversion_penalty = 0;                       // BodyDefinition::inversion_penalty
  DamageRule damage_rule = DamageRule::centre_bonds;  // BodyDefinition::damage_rule
  const ForceModelKernels* model = nullptr;           // BodyDefinition::model (null: CKPD)
  double strain_measure = 0.5;                        // BodyDefinition::strain_measure
  StateBasedConstants state_based;                    // BodyDefinition::state_based
  ForceForm force_form = ForceForm::own_family;       // BodyDefinition::force_form

  // Reference data per point, fixed for the run.
  std::vector<Vec3> reference_position;
  std::vector<double> volume;
  std::vector<double> beta;  // fullness of the family
  // What the fullness looked like before any cap (reported in the setup and the summary).
  bool beta_cap = false;                // BodyDefinition::cap_beta
  std::size_t beta_capped_points = 0;   // points whose raw beta exceeded 1 (+1e-9) and was capped
  double beta_max_raw = 0;              // the largest raw beta
  std::vector<double> dv1, dv2, dv3;    // effective volumes VH/N1, VH^2/N2, VH^3/N3
  std::vector<std::uint32_t> n2, n3;    // ordered, non-degenerate sets (N1 = family size)
  std::vector<double> stiffness_bound;  // k_i: bound of the linearised stiffness, N/m^3/m
  std::vector<std::uint8_t> no_failure;

  // Bonds: CSR family and one byte per stored bond (1 intact, 0 failed for good).
  BondFamily family;
  std::vector<std::uint8_t> bond_intact;
  // The lattice stencil shared by all points, or null (general path); the note says why not.
  std::shared_ptr<const LatticeStencil> stencil;
  std::string stencil_note;
  // A body without two- and three-neighbour sets: its bonds' reference lengths, each bond once
  // (upper_bonds.hpp; the bond-only kernel's table); null for the others.
  std::shared_ptr<const UpperBonds> upper_bonds;
  // A body with sets on the general path: its centres' adjacency rows (upper_rows.hpp), or null
  // (a stencil, no sets, or beyond the table's memory limit).
  std::shared_ptr<const UpperRows> upper_rows;
  // Computed once from the reference configuration (make_body).
  SetScreens screens;

  // State.
  std::vector<Vec3> displacement;
  std::vector<Vec3> velocity;
  std::vector<Vec3> acceleration;
  std::vector<Vec3> external_force_density;
  std::vector<Vec3> force_density;            // total: internal + external + contact
  std::vector<double> strain_energy_density;  // W1/2 + W2/3 + W3/4, filled on request
  // Distributed force work (MPI, src/engine/force_sharing.hpp, src/engine/distribution.hpp):
  // when not empty, the symmetric kernel evaluates only the sets centred at points i with
  // owned_centres[i] != 0 (this rank's share); the ranks' partial force and energy buffers are
  // then summed in rank order.
  std::vector<std::uint8_t> owned_centres;
  // A body restricted to a rank's owned points and their halo (sub_body.hpp): when not empty,
  // what the body books is that of the points with booked_points[i] != 0 alone, so that the
  // ranks' figures add up to the whole body's: strain_energy, the damage step's dissipated energy
  // (each point's own share) and failed bonds (a bond counted at its lower end),
  // failed_bond_count, point damage maxima. Empty: every point (a whole body).
  std::vector<std::uint8_t> booked_points;
  bool books(std::size_t i) const { return booked_points.empty() || booked_points[i] != 0; }

  std::size_t size() const { return reference_position.size(); }
  Vec3 current_position(std::size_t i) const { return reference_position[i] + displacement[i]; }
  bool has_pairs() const { return constants.c2 != 0; }
  bool has_triples() const { return constants.c3 != 0; }
  std::size_t bond_count() const { return family.bond_entries() / 2; }
  std::uint64_t total_two_neighbour() const;    // sum of N2 (ordered)
  std::uint64_t total_three_neighbour() const;  // sum of N3 (ordered)
  double mass() const;
};

// Validates the definition (throws std::invalid_argument naming what is wrong), builds the
// families, counts the interactions, sets effective volumes and the stiffness bound, applies
// pre-cracks.
Body make_body(BodyDefinition definition);

// The smallest stable time step of this body alone: 2 sqrt(rho / max_i k_i) (central-difference
// limit with the largest eigenvalue bounded by k_i / rho). Also returns the limiting point.
struct StableStep {
  double dt = std::numeric_limits<double>::infinity();
  std::size_t point = 0;
};
StableStep stable_step(const Body& body);

// Point i's stiffness bound split by interaction family (the largest eigenvalue of each
// family's part of the bound matrix), to tell which term limits the time step.
struct StiffnessTerms {
  double bonds = 0, pairs = 0, triples = 0;
};
StiffnessTerms stiffness_terms(const Body& body, std::size_t i);

// ForceForm::energy_consistent: per family n (bonds, triangles, tetrahedra), the largest
// V^c dVn^c over point i and its bond family, over V^i dVn^i (1 where all are equal, as in a
// lattice's interior; 1 for an empty family): the factor of the family's own-family bound.
std::array<double, 3> conservative_bound_scale(const Body& body, std::size_t i);

// Sum over points of strain_energy_density * volume (call after an energy evaluation).
double strain_energy(const Body& body);

}  // namespace ckpd
