#pragma once
// CKPD internal force density (THEORY.md section 2) with every interaction evaluated ONCE.
//
// The reference kernel (reference/internal_force.hpp) visits each point's family and so computes
// every bond twice, every triangle three times and every tetrahedron four times. The sums are exact
// rewritings of per-set terms (THEORY.md section 2), so here each unordered set is enumerated
// once, from its smallest-index vertex i, and its geometry gives every vertex c its share:
//   bond {i,j}:        c1 (1/L - 1/l) dx^ic dV1^c              (if the bond is intact)
//   triangle {i,j,k}:  -2 C2 dV2^c (|a|/A - 1) d|a|/dx^c         (if c's two bonds are intact)
//   tetrahedron:       -6 C3 dV3^c (v/|V| - sign v) dv/dx^c      (if c's three bonds are intact)
// or, under DamageRule::all_edges, if all three (six) edges of the set are intact.
// A set is left out for vertex c exactly when the reference leaves it out of c's family: the
// degeneracy test is made from c's own perspective (THEORY.md section 1), with a screen that
// decides without the extra arithmetic whenever the answer cannot differ between vertices.
//
// The result equals compute_internal_force to round-off and is deterministic for a given
// number of OpenMP threads: each thread accumulates into its own whole-body arrays over a
// static schedule, and the arrays are summed in thread order.
#include <cstdint>
#include <memory>
#include <vector>

#include "bodies/body.hpp"

namespace ckpd {

// What one evaluation did (sets counted once; those with no active, non-degenerate vertex
// are not counted).
struct SymmetricKernelStats {
  std::uint64_t bonds = 0;
  std::uint64_t triangles = 0;
  std::uint64_t tetrahedra = 0;
  // Of those, the ill-conditioned ones (slivers) evaluated vertex by vertex.
  std::uint64_t triangles_per_vertex = 0;
  std::uint64_t tetrahedra_per_vertex = 0;
  // Counted only in evaluations with energy: evaluated sets whose current signed volume has the
  // sign opposite to the reference one (tetrahedra), or signed area (triangles of 2D bodies).
  std::uint64_t inverted_triangles = 0;
  std::uint64_t inverted_tetrahedra = 0;
};

struct FailureUpdate;          // damage.hpp
struct SymmetricKernelThread;  // per-thread scratch, defined in symmetric/context.hpp

// Scratch that survives between calls so that steady-state evaluations allocate nothing. It
// only grows. One workspace must not be used by two calls at the same time.
class SymmetricKernelWorkspace {
 public:
  SymmetricKernelWorkspace();
  ~SymmetricKernelWorkspace();
  SymmetricKernelWorkspace(const SymmetricKernelWorkspace&) = delete;
  SymmetricKernelWorkspace& operator=(const SymmetricKernelWorkspace&) = delete;

  SymmetricKernelThread& thread(std::size_t t) { return *threads_[t]; }
  void ensure_threads(std::size_t count);

  // With damage: per point, whether some bond of its family has failed (kSomeFailed) or every
  // one (kAllFailed), and where it has some, the CSR position of its first neighbour j > i.
  std::vector<std::uint8_t> row_failed;
  std::vector<std::size_t> row_upper;
  // On the stencil path, for a point with some failed bonds: its failed upper bonds as a bit row
  // over its own upper slots (the stencil's words per point; rows of other points are stale).
  std::vector<std::uint64_t> failed_upper;
  // The far field (far_field.hpp): when set, centres i with skip_centre[i] != 0 are not
  // processed (nothing exact among i and its upper family); null: every centre.
  const std::uint8_t* skip_centre = nullptr;
  // The far field's exact points (exact_point[i] != 0): when set, a set none of whose vertices
  // is exact is not evaluated (its forces would land on linear points only, whose rows the
  // linear operator overwrites); null: every set of a processed centre.
  const std::uint8_t* exact_point = nullptr;
  // The fused damage step of bond-only bodies (symmetric/bond_only.hpp): per stored bond and
  // per point, whether it fails now (all zero between calls).
  std::vector<std::uint8_t> failing, touched;

 private:
  std::vector<std::unique_ptr<SymmetricKernelThread>> threads_;
};

// body.force_density = b1 + b2 + b3 (overwritten); with `with_energy`, also
// body.strain_energy_density = W1/2 + W2/3 + W3/4. Same contract as compute_internal_force.
// This overload keeps its scratch in a workspace private to the calling (host) thread.
// body.inversion_penalty adds the inversion penalty exactly as compute_internal_force does.
SymmetricKernelStats compute_internal_force_symmetric(Body& body, bool with_energy);
// The damage step and the forces after it: `failure` = fail_overstretched_bonds(body,
// half_drift) (damage.hpp), then compute_internal_force_symmetric(body, with_energy) on the
// bonds that survive it, with the same results bit for bit. A bond-only body (no two- or
// three-neighbour sets) does both in one pass over its bonds (symmetric/bond_only.hpp).
SymmetricKernelStats fail_bonds_and_compute_internal_force(Body& body, bool with_energy,
                                                           double half_drift,
                                                           FailureUpdate& failure);
// Whether a body is evaluated on the stencil path: it has a lattice stencil (body.stencil) with
// the tables its interaction families need, and it has two- or three-neighbour interactions.
// Resetting body.stencil selects the general path (benchmarks and tests compare the two).
bool uses_lattice_stencil(const Body& body);
SymmetricKernelStats compute_internal_force_symmetric(Body& body, bool with_energy,
                                                      SymmetricKernelWorkspace& workspace);

// The kernel's degeneracy screens for a body (Body::screens; make_body sets them once).
SetScreens set_screens(const Body& body);

// The ordered, non-degenerate two- and three-neighbour counts per point as this kernel's
// enumeration and degeneracy decisions see them (all bonds, intact or not). They must equal
// body.n2 and body.n3; tests use this to prove that the per-vertex decisions agree.
void count_interactions_symmetric(const Body& body, std::vector<std::uint32_t>& n2,
                                  std::vector<std::uint32_t>& n3);

}  // namespace ckpd
