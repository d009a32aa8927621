#pragma once
// The damage step of a force model (damage.hpp has the contract): which bonds fail now, by the
// model's rule (Model::bond_fails), and the strain energy their failure takes out of the body.
#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "bodies/damage.hpp"
#include "bodies/point_kernel.hpp"

namespace ckpd {

namespace bond_failure_detail {
// A screen before breaks_now for models that fail a bond above a critical stretch s_c: a bond
// with l^2 <= (1 + s_c)^2 L^2 (1 - 1e-9) has a stretch below s_c by far more than the exact
// test's rounding, so it cannot fail, and is passed over without the two square roots and the
// division (the test took 3.5 % of a far-field sphere-disc run, perf). The bonds that remain
// get the exact test: the same bonds fail. -1 (no screen) for other models.
template <class Model>
double stretch_screen(const Model& model) {
  if constexpr (requires { model.critical_stretch; }) {
    const double s = 1 + model.critical_stretch;
    return s * s * (1 - 1e-9);  // +inf with no failure: every bond passes over
  } else {
    return -1;
  }
}

// Whether the intact bond stored at k in point i's row fails now: the model's rule at its
// stretch, and neither end in a no-failure zone. Both stored directions give the same answer.
template <class Model>
bool breaks_now(const Model& model, const Body& body, bool protect, std::size_t i, std::size_t k) {
  if (!body.bond_intact[k]) return false;
  const std::uint32_t j = body.family.neighbour[k];
  if (protect && (body.no_failure[i] || body.no_failure[j])) return false;
  return model.bond_fails(bond_stretch(body.reference_position[j] - body.reference_position[i],
                                       body.displacement[j] - body.displacement[i]));
}

// Bonds only (no two- or three-neighbour sets): a failing bond {i, j} takes exactly its own
// energy out of the two ends' sums, V^i dV1^i psi1/2 + V^j dV1^j psi1/2 (half of W1's psi1 per
// stored direction), psi1 at the booking displacement u - half_drift v. The half of the bond
// stored at k in point i's row:
template <class Model>
double failing_bond_energy(const Model& model, const Body& body, std::size_t i, std::size_t k,
                           double half_drift) {
  const std::uint32_t j = body.family.neighbour[k];
  const Vec3 dX = body.reference_position[j] - body.reference_position[i];
  const Vec3 du = (body.displacement[j] - half_drift * body.velocity[j]) -
                  (body.displacement[i] - half_drift * body.velocity[i]);
  return 0.5 * model.bond_energy(dX.norm(), bond_stretch(dX, du));
}

// Point i's share of the energy its failing bonds take: the sum over its row's failing entries
// in CSR order, times V^i dV1^i. `failing(k)` says whether the entry at k fails now.
template <class Model, class Failing>
double failing_row_energy(const Model& model, const Body& body, std::size_t i, double half_drift,
                          Failing&& failing) {
  double mine = 0;
  for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k)
    if (failing(k)) mine += failing_bond_energy(model, body, i, k, half_drift);
  return mine * body.dv1[i] * body.volume[i];
}

// One pass over the bonds does the test, the failure and the bookkeeping: no per-point
// re-evaluation. (The bond-only kernel, symmetric/bond_only.hpp, does the test and the failure
// inside its own bond pass and books the same sums in the same order.)
template <class Model>
FailureUpdate fail_bonds_only(const Model& model, Body& body, double half_drift) {
  const std::size_t n = body.size();
  const bool protect = !body.no_failure.empty();
  // Per-point sums, added in point order below: the total does not depend on the thread count.
  // (Kept between calls by the calling thread; the workers write through this reference.)
  thread_local std::vector<double> kept;
  std::vector<double>& lost = kept;
  lost.assign(n, 0.0);
  std::size_t failed = 0;
#pragma omp parallel for schedule(static) reduction(+ : failed)
  for (std::size_t i = 0; i < n; ++i) {
    // Each stored direction fails its own flag; the other direction is decided by the same
    // stretch when its row is visited.
    const bool booked = body.books(i);
    lost[i] = failing_row_energy(model, body, i, half_drift, [&](std::size_t k) {
      if (!breaks_now(model, body, protect, i, k)) return false;
      body.bond_intact[k] = 0;
      if (booked && i < body.family.neighbour[k]) ++failed;
      return true;
    });
  }
  FailureUpdate result;
  result.failed = failed;
  for (std::size_t i = 0; i < n; ++i)
    if (body.books(i)) result.dissipated += lost[i];
  return result;
}

// The buffers of fail_overstretched_bonds_of, kept between calls by the calling thread so that a
// time step allocates nothing once they have grown (tests/allocation). The parallel regions
// below reach them through references bound outside the regions: every worker then writes the
// calling thread's buffers, not a thread_local of its own.
struct FailureWorkspace {
  std::vector<std::uint8_t> failing, touched, ends;
  std::vector<std::uint32_t> points;
  std::vector<double> lost;
  std::vector<Vec3> end_of_step;
  // One family scratch per worker, by omp_get_thread_num(). Not thread_local in the workers:
  // libgomp ends pooled threads when a region runs with fewer (an if clause elsewhere), and
  // the new threads would start with empty scratch.
  std::vector<SwitchingFamily> scratch;
};
inline FailureWorkspace& failure_workspace() {
  thread_local FailureWorkspace w;
  return w;
}
}  // namespace bond_failure_detail

template <class Model>
std::size_t update_bond_failure_of(const Model& model, Body& body) {
  if (!body.damage_enabled) return 0;
  const std::size_t n = body.size();
  const bool protect = !body.no_failure.empty();
  std::size_t failed = 0;
#pragma omp parallel for schedule(static) reduction(+ : failed)
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k) {
      if (bond_failure_detail::breaks_now(model, body, protect, i, k)) {
        body.bond_intact[k] = 0;
        if (i < body.family.neighbour[k] && body.books(i)) ++failed;
      }
    }
  }
  return failed;
}

template <class Model>
FailureUpdate fail_overstretched_bonds_of(const Model& model, Body& body, double half_drift) {
  FailureUpdate result;
  if (!body.damage_enabled) return result;
  const bool sets = (Model::kTriangles && model.has_triangles()) ||
                    (Model::kTetrahedra && model.has_tetrahedra());
  if (!sets) return bond_failure_detail::fail_bonds_only(model, body, half_drift);
  // The bonds about to fail, decided at the end-of-step displacement (update_bond_failure's
  // test), and the points that hold one.
  const std::size_t n = body.size();
  const bool protect = !body.no_failure.empty();
  bond_failure_detail::FailureWorkspace& w = bond_failure_detail::failure_workspace();
  std::vector<std::uint8_t>& failing = w.failing;
  std::vector<std::uint8_t>& touched = w.touched;
  std::vector<std::uint8_t>& ends = w.ends;
  // All zero between calls (the flags set below are cleared where they are applied), so a step
  // clears nothing unless the body's bond count differs from the last body's.
  if (failing.size() != body.family.neighbour.size())
    failing.assign(body.family.neighbour.size(), 0);
  std::size_t failed = 0, flagged = 0;
  const double screen = bond_failure_detail::stretch_screen(model);
  // Each bond is tested once, from its lower end, and both stored directions are flagged: they
  // compute the same stretch bit for bit (the offsets are negated exactly), so this fails the
  // bonds update_bond_failure fails. The other direction's position is looked up only for the
  // bonds that fail; each flag is written by one iteration alone. Chunks, not halves: the bonds
  // that pass the screen lie together (a bent plate's tensile face is one half of its points).
#pragma omp parallel for schedule(static, 256) reduction(+ : failed, flagged)
  for (std::size_t i = 0; i < n; ++i) {
    const auto row = body.family.neighbour.begin();
    const std::size_t end = body.family.offset[i + 1];
    const std::size_t upper = static_cast<std::size_t>(
        std::upper_bound(row + static_cast<std::ptrdiff_t>(body.family.offset[i]),
                         row + static_cast<std::ptrdiff_t>(end), static_cast<std::uint32_t>(i)) -
        row);
    const Vec3 Xi = body.reference_position[i], ui = body.displacement[i];
    for (std::size_t k = upper; k < end; ++k) {
      if (screen >= 0) {
        const std::uint32_t j = body.family.neighbour[k];
        const Vec3 dX = body.reference_position[j] - Xi;
        if (!((dX + (body.displacement[j] - ui)).squaredNorm() > screen * dX.squaredNorm()))
          continue;
      }
      if (!bond_failure_detail::breaks_now(model, body, protect, i, k)) continue;
      failing[k] = 1;
      failing[FamilyScratch::bond_position(body, body.family.neighbour[k],
                                           static_cast<std::uint32_t>(i))] = 1;
      failed += body.books(i);
      ++flagged;
    }
  }
  // (On a restriction a step may fail only bonds booked elsewhere: their flags still change.)
  if (flagged == 0) return result;
  ends.assign(n, 0);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k)
      if (failing[k]) {
        ends[i] = 1;
        break;
      }
  touched = ends;
  if (body.damage_rule == DamageRule::all_edges) {
    // A failing bond j-k also switches off, for every common neighbour i, the sets of i's own
    // family that hold the edge j-k: their energy leaves i's sum too. Every such i is bonded to
    // j (the set's edges are bonds), so the ends' neighbours are all the points that change:
    // marked from the ends' rows (few), not by a pass over every row.
    for (std::size_t j = 0; j < n; ++j) {
      if (!ends[j]) continue;
      for (std::size_t k = body.family.offset[j]; k < body.family.offset[j + 1]; ++k)
        touched[body.family.neighbour[k]] = 1;
    }
  }
  std::vector<std::uint32_t>& points = w.points;
  points.clear();
  // Room for every point at once: a step that touches more points than any before allocates
  // nothing either.
  points.reserve(n);
  w.lost.reserve(n);
  std::size_t largest_family = 0;  // every worker's scratch sized once for any point
  for (std::size_t i = 0; i < n; ++i) {
    largest_family = std::max(largest_family, body.family.offset[i + 1] - body.family.offset[i]);
    // A restriction's halo points hold cut families: their shares are booked by their owners.
    if (touched[i] && body.books(i)) points.push_back(static_cast<std::uint32_t>(i));
  }
  std::vector<double>& lost = w.lost;
  lost.assign(points.size(), 0.0);
  // Book at the step's midpoint (see damage.hpp): the energies are read at u - half_drift v, and
  // the end-of-step displacement is put back bit for bit afterwards.
  std::vector<Vec3>& end_of_step = w.end_of_step;
  if (half_drift != 0) {
    end_of_step = body.displacement;
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) body.displacement[i] -= half_drift * body.velocity[i];
  }
  // Only the sets the failures switch off are evaluated (before the flags change): their
  // energy is what each point's sum loses.
  const std::size_t workers = static_cast<std::size_t>(omp_get_max_threads());
  if (w.scratch.size() < workers) w.scratch.resize(workers);
  std::vector<SwitchingFamily>& scratches = w.scratch;
#pragma omp parallel
  {
    SwitchingFamily& scratch = scratches[static_cast<std::size_t>(omp_get_thread_num())];
    scratch.reserve(largest_family, n);
#pragma omp for schedule(dynamic, 4)
    for (std::size_t p = 0; p < points.size(); ++p)
      lost[p] = switched_off_energy_density_of(model, body, points[p], scratch, failing, ends);
  }
  // Copied back, not moved: the displacement keeps its buffer (the Python module's numpy views
  // of it must stay valid across steps).
  if (half_drift != 0) std::copy(end_of_step.begin(), end_of_step.end(), body.displacement.begin());
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < failing.size(); ++k)
    if (failing[k]) {
      body.bond_intact[k] = 0;
      failing[k] = 0;
    }
  // Summed in point order, so the result does not depend on the thread schedule.
  double dissipated = 0;
  for (std::size_t p = 0; p < points.size(); ++p) dissipated += body.volume[points[p]] * lost[p];
  result.failed = failed;
  result.dissipated = dissipated;
  return result;
}

}  // namespace ckpd
