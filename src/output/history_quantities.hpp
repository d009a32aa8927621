#pragma once
// History columns chosen in the case (`output: {history: [...]}`), after the default ones: one
// row of the table below per quantity, with the columns it adds and how it is computed from the
// simulation's state at a history row (an evaluation with energy).
//   momentum, centre_of_mass, mean_velocity (x, y, z), kinetic_energy, strain_energy,
//   broken_bonds, fragments                                  of one body;
//   reaction_force (x, y, z)  of a region of one body: what holds its points to their prescribed
//                             motion, sum over the region of V (rho a - f), f every force on the
//                             point (internal, external, contact); zero for free points;
//   contact_force (x, y, z)   on the first of two bodies from the second: the sum of V f over the
//                             first body less its external loads (its internal forces sum to
//                             zero); the first body must touch no other body;
//   contact_energy            between two bodies: the scene's contact energy, when they are the
//                             scene's only contact pair (the contact library sums over pairs).
#include <functional>
#include <string>
#include <vector>

#include "src/engine/simulation.hpp"

namespace ckpd {

struct HistoryQuantityKind {
  std::string name;
  int bodies = 1;                    // how many bodies it names
  bool region = false;               // it takes a region of its body
  std::vector<std::string> columns;  // suffixes: {"x", "y", "z"}, or {""} for one column
  std::function<void(const Simulation&, const HistoryQuantity&, std::vector<double>&)> compute;
};

const std::vector<HistoryQuantityKind>& history_quantity_table();
const HistoryQuantityKind* find_history_quantity(const std::string& name);
std::string known_history_quantities();  // "momentum, centre_of_mass, ..."

// Checks what depends on the whole scene (contact partners); "" when fine, else the reason.
std::string history_quantity_problem(const Scene& scene, const HistoryQuantity& q);

// The columns of `q`, e.g. momentum_ball_x, momentum_ball_y, momentum_ball_z.
std::vector<std::string> history_columns(const HistoryQuantity& q);
// Its values now, one per column.
std::vector<double> history_values(const Simulation& sim, const HistoryQuantity& q);

}  // namespace ckpd
