#include "bodies/damage.hpp"

#include <algorithm>
#include <stdexcept>

#include "bodies/family_scratch.hpp"
#include "bodies/internal_force.hpp"

namespace ckpd {

namespace {

double orientation_2d(const Vec3& p, const Vec3& q, const Vec3& r) {
  return (q.x() - p.x()) * (r.y() - p.y()) - (q.y() - p.y()) * (r.x() - p.x());
}

bool crosses_segment(const Vec3& a, const Vec3& b, const Vec3& c0, const Vec3& c1) {
  const double sa = orientation_2d(c0, c1, a), sb = orientation_2d(c0, c1, b);
  if (!((sa < 0 && sb > 0) || (sa > 0 && sb < 0))) return false;
  const double s0 = orientation_2d(a, b, c0), s1 = orientation_2d(a, b, c1);
  return (s0 <= 0 && s1 >= 0) || (s0 >= 0 && s1 <= 0);
}

Vec3 polygon_normal(const std::vector<Vec3>& c) {
  Vec3 n = Vec3::Zero();  // Newell's method: robust for any planar polygon
  for (std::size_t k = 0; k < c.size(); ++k) n += c[k].cross(c[(k + 1) % c.size()]);
  return n;
}

bool crosses_polygon(const Vec3& a, const Vec3& b, const std::vector<Vec3>& c) {
  const Vec3 n = polygon_normal(c);
  const double da = n.dot(a - c[0]), db = n.dot(b - c[0]);
  if (!((da < 0 && db > 0) || (da > 0 && db < 0))) return false;
  const Vec3 x = a + (b - a) * (da / (da - db));
  bool any_negative = false, any_positive = false;
  for (std::size_t k = 0; k < c.size(); ++k) {
    const double side = n.dot((c[(k + 1) % c.size()] - c[k]).cross(x - c[k]));
    any_negative |= side < 0;
    any_positive |= side > 0;
  }
  return !(any_negative && any_positive);
}

}  // namespace

bool segment_crosses_precrack(const Vec3& a, const Vec3& b, const Precrack& crack) {
  if (crack.corners.size() == 2) return crosses_segment(a, b, crack.corners[0], crack.corners[1]);
  return crosses_polygon(a, b, crack.corners);
}

std::size_t apply_precrack(Body& body, const Precrack& crack) {
  const std::string who = "body '" + body.name + "': pre-crack ";
  if (body.dimension == 2) {
    if (crack.corners.size() != 2)
      throw std::invalid_argument(who + "of a 2D body is a segment: give 2 points");
    if ((crack.corners[1] - crack.corners[0]).norm() == 0)
      throw std::invalid_argument(who + "has zero length");
  } else {
    if (crack.corners.size() < 3)
      throw std::invalid_argument(who + "of a 3D body is a planar polygon: give 3 or more corners");
    const Vec3 n = polygon_normal(crack.corners);
    if (n.norm() == 0) throw std::invalid_argument(who + "has zero area");
    for (const Vec3& p : crack.corners) {
      const double off = std::abs(n.normalized().dot(p - crack.corners[0]));
      if (off > 1e-9 * std::sqrt(n.norm()))
        throw std::invalid_argument(who + "corners are not in one plane");
    }
  }
  std::size_t cut = 0;
  for (std::size_t i = 0; i < body.size(); ++i) {
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k) {
      const std::uint32_t j = body.family.neighbour[k];
      // Test the segment in one fixed orientation so both stored directions agree exactly.
      const std::size_t lo = std::min<std::size_t>(i, j), hi = std::max<std::size_t>(i, j);
      if (segment_crosses_precrack(body.reference_position[lo], body.reference_position[hi],
                                   crack)) {
        if (body.bond_intact[k] && i < j) ++cut;
        body.bond_intact[k] = 0;
      }
    }
  }
  // Failed bonds are only skipped by the kernels when damage bookkeeping is on; a pre-cracked
  // body without a critical stretch (no damage growth) must still not carry force across the
  // crack. update_bond_failure then compares with s_c = +inf and fails nothing.
  if (cut > 0) body.damage_enabled = true;
  return cut;
}

namespace {
// Whether the intact bond stored at k in point i's row fails now: stretch over the critical
// stretch and neither end in a no-failure zone. Both stored directions give the same answer.
bool breaks_now(const Body& body, bool protect, std::size_t i, std::size_t k) {
  if (!body.bond_intact[k]) return false;
  const std::uint32_t j = body.family.neighbour[k];
  if (protect && (body.no_failure[i] || body.no_failure[j])) return false;
  return bond_stretch(body.reference_position[j] - body.reference_position[i],
                      body.displacement[j] - body.displacement[i]) > body.critical_stretch;
}
}  // namespace

std::size_t update_bond_failure(Body& body) {
  if (!body.damage_enabled) return 0;
  const std::size_t n = body.size();
  const bool protect = !body.no_failure.empty();
  std::size_t failed = 0;
#pragma omp parallel for schedule(static) reduction(+ : failed)
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k) {
      if (breaks_now(body, protect, i, k)) {
        body.bond_intact[k] = 0;
        if (i < body.family.neighbour[k]) ++failed;
      }
    }
  }
  return failed;
}

namespace {
// Bonds only (no two- or three-neighbour sets): a failing bond {i, j} takes exactly its own
// energy out of the two ends' sums, V^i dV1^i w + V^j dV1^j w with w = c1 L s^2 / 4 (half of
// W1's 1/2 c1 L s^2 per stored direction), s its stretch at the booking displacement. One pass
// over the bonds does the test, the failure and the bookkeeping: no per-point re-evaluation.
FailureUpdate fail_overstretched_bonds_only(Body& body, double half_drift) {
  const std::size_t n = body.size();
  const bool protect = !body.no_failure.empty();
  const double c1 = body.constants.c1;
  // Per-point sums, added in point order below: the total does not depend on the thread count.
  // (Kept between calls by the calling thread; the workers write through this reference.)
  thread_local std::vector<double> kept;
  std::vector<double>& lost = kept;
  lost.assign(n, 0.0);
  std::size_t failed = 0;
#pragma omp parallel for schedule(static) reduction(+ : failed)
  for (std::size_t i = 0; i < n; ++i) {
    double mine = 0;
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k) {
      if (!breaks_now(body, protect, i, k)) continue;
      // Each stored direction fails its own flag; the other direction is decided by the same
      // stretch when its row is visited.
      body.bond_intact[k] = 0;
      const std::uint32_t j = body.family.neighbour[k];
      if (i < j) ++failed;
      const Vec3 dX = body.reference_position[j] - body.reference_position[i];
      const Vec3 du = (body.displacement[j] - half_drift * body.velocity[j]) -
                      (body.displacement[i] - half_drift * body.velocity[i]);
      const double s = bond_stretch(dX, du);
      mine += 0.25 * c1 * dX.norm() * s * s;
    }
    lost[i] = mine * body.dv1[i] * body.volume[i];
  }
  FailureUpdate result;
  result.failed = failed;
  for (std::size_t i = 0; i < n; ++i) result.dissipated += lost[i];
  return result;
}
}  // namespace

FailureUpdate fail_overstretched_bonds(Body& body, double half_drift) {
  FailureUpdate result;
  if (!body.damage_enabled) return result;
  if (!body.has_pairs() && !body.has_triples())
    return fail_overstretched_bonds_only(body, half_drift);
  // Points with a bond about to fail (found with the same test update_bond_failure applies).
  const std::size_t n = body.size();
  const bool protect = !body.no_failure.empty();
  std::vector<std::uint8_t> touched(n, 0);
  bool any = false;
#pragma omp parallel for schedule(static) reduction(|| : any)
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k) {
      if (breaks_now(body, protect, i, k)) {
        touched[i] = 1;
        any = true;
        break;
      }
    }
  }
  if (!any) return result;
  if (body.damage_rule == DamageRule::all_edges) {
    // A failing bond j-k also switches off, for every common neighbour i, the sets of i's own
    // family that hold the edge j-k: their energy leaves i's sum too. Every such i is bonded to
    // j (the set's edges are bonds), so the ends' neighbours are all the points that change.
    std::vector<std::uint8_t> ends = touched;
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      if (ends[i]) continue;
      for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k) {
        if (ends[body.family.neighbour[k]]) {
          touched[i] = 1;
          break;
        }
      }
    }
  }
  std::vector<std::uint32_t> points;
  for (std::size_t i = 0; i < n; ++i)
    if (touched[i]) points.push_back(static_cast<std::uint32_t>(i));
  std::vector<double> before(points.size()), after(points.size());
  // Book at the step's midpoint (see the header): the energies are read at u - half_drift v, and
  // the end-of-step displacement is put back bit for bit afterwards.
  std::vector<Vec3> end_of_step;
  if (half_drift != 0) {
    end_of_step = body.displacement;
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) body.displacement[i] -= half_drift * body.velocity[i];
  }
#pragma omp parallel
  {
    FamilyScratch scratch;
#pragma omp for schedule(dynamic, 4)
    for (std::size_t p = 0; p < points.size(); ++p)
      before[p] = evaluate_point(body, points[p], scratch).strain_energy_density();
#pragma omp single
    {
      // Decided at the end-of-step displacement, like update_bond_failure alone.
      if (half_drift != 0) std::swap(body.displacement, end_of_step);
      result.failed = update_bond_failure(body);
      if (half_drift != 0) std::swap(body.displacement, end_of_step);
    }
#pragma omp for schedule(dynamic, 4)
    for (std::size_t p = 0; p < points.size(); ++p)
      after[p] = evaluate_point(body, points[p], scratch).strain_energy_density();
  }
  // Copied back, not moved: the displacement keeps its buffer (the Python module's numpy views
  // of it must stay valid across steps).
  if (half_drift != 0) std::copy(end_of_step.begin(), end_of_step.end(), body.displacement.begin());
  // Summed in point order, so the result does not depend on the thread schedule.
  double dissipated = 0;
  for (std::size_t p = 0; p < points.size(); ++p)
    dissipated += body.volume[points[p]] * (before[p] - after[p]);
  result.dissipated = dissipated;
  return result;
}

void point_damage(const Body& body, std::vector<double>& damage) {
  damage.resize(body.size());
  for (std::size_t i = 0; i < body.size(); ++i) {
    const std::size_t begin = body.family.offset[i], end = body.family.offset[i + 1];
    std::size_t intact = 0;
    for (std::size_t k = begin; k < end; ++k) intact += body.bond_intact[k];
    damage[i] =
        end > begin ? 1.0 - static_cast<double>(intact) / static_cast<double>(end - begin) : 0.0;
  }
}

double max_point_damage(const Body& body) {
  std::vector<double> d;
  point_damage(body, d);
  return d.empty() ? 0.0 : *std::max_element(d.begin(), d.end());
}

std::size_t failed_bond_count(const Body& body) {
  std::size_t failed = 0;
  for (auto b : body.bond_intact) failed += b == 0;
  return failed / 2;
}

}  // namespace ckpd
