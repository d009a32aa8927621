#include "bodies/damage.hpp"

#include <algorithm>
#include <stdexcept>

#include "bodies/force_model.hpp"

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

std::size_t update_bond_failure(Body& body) {
  return force_model(body).update_failure(body);
}

FailureUpdate fail_overstretched_bonds(Body& body, double half_drift) {
  return force_model(body).fail_and_book(body, half_drift);
}

namespace {

double damage_of_point(const Body& body, std::size_t i) {
  const std::size_t begin = body.family.offset[i], end = body.family.offset[i + 1];
  std::size_t intact = 0;
  for (std::size_t k = begin; k < end; ++k) intact += body.bond_intact[k];
  return end > begin ? 1.0 - static_cast<double>(intact) / static_cast<double>(end - begin) : 0.0;
}

}  // namespace

void point_damage(const Body& body, std::vector<double>& damage) {
  damage.resize(body.size());
  for (std::size_t i = 0; i < body.size(); ++i) damage[i] = damage_of_point(body, i);
}

// No buffer: a distributed run books it every step.
double max_point_damage(const Body& body) {
  double largest = 0;
  for (std::size_t i = 0; i < body.size(); ++i)
    if (body.books(i)) largest = std::max(largest, damage_of_point(body, i));
  return largest;
}

std::size_t failed_bond_count(const Body& body) {
  std::size_t failed = 0;
  if (body.booked_points.empty()) {
    for (auto b : body.bond_intact) failed += b == 0;
    return failed / 2;
  }
  // A restriction: each bond at its lower end, whose family the restriction holds whole.
  for (std::size_t i = 0; i < body.size(); ++i) {
    if (!body.booked_points[i]) continue;
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k)
      failed += body.bond_intact[k] == 0 && body.family.neighbour[k] > i;
  }
  return failed;
}

}  // namespace ckpd
