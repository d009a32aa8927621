#pragma once
// History columns chosen in the case (`output: {history: [...]}`), after the default ones: one
// row of the table below per quantity, with the columns it adds and how it is computed from the
// simulation's state at a history row (an evaluation with energy): sums over the points, which the
// ranks of a distributed run add over their own points, except fragments (labelled on the whole
// body, gathered).
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

// Where a row's values are taken from: the whole scene, or in a distributed run a rank's part
// (`distribution` set), each rank adding the points it books so that the sums over ranks are the
// whole scene's.
struct HistorySource {
  const Simulation& sim;
  const Scene& scene;
  const Distribution* distribution = nullptr;
  bool root = true;  // adds what is already the whole scene's (counts, the contact energy)
};

struct HistoryQuantityKind {
  std::string name;
  int bodies = 1;                    // how many bodies it names
  bool region = false;               // it takes a region of its body
  std::vector<std::string> columns;  // suffixes: {"x", "y", "z"}, or {""} for one column
  // Labelled on the whole scene (fragments): a distributed run gathers it to rank 0 for the row.
  bool whole = false;
  std::size_t sums = 1;  // how many sums `add` adds to
  std::function<void(const HistorySource&, const HistoryQuantity&, double* sums)> add;
  // The columns from the sums over ranks; null: the sums are the columns.
  std::function<void(const double* sums, double* columns)> finish;
};

const std::vector<HistoryQuantityKind>& history_quantity_table();
const HistoryQuantityKind* find_history_quantity(const std::string& name);
std::string known_history_quantities();  // "momentum, centre_of_mass, ..."

// Checks what depends on the whole scene (contact partners); "" when fine, else the reason.
std::string history_quantity_problem(const Scene& scene, const HistoryQuantity& q);

// The columns of `q`, e.g. momentum_ball_x, momentum_ball_y, momentum_ball_z.
std::vector<std::string> history_columns(const HistoryQuantity& q);
// Whether a row with these quantities needs the whole scene on rank 0 (a distributed run's
// gather before it).
bool history_needs_whole_scene(const std::vector<HistoryQuantity>& chosen);
// Their values now, one per column, quantity after quantity. In a distributed run a collective:
// every rank adds its booked points' share and the sums are added in rank order (the same bits on
// every rank); with a whole-scene quantity rank 0's whole scene must have been gathered.
std::vector<double> history_values(const Simulation& sim,
                                   const std::vector<HistoryQuantity>& chosen);

}  // namespace ckpd
