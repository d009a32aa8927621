#include "src/engine/contact_coupling.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include "contact/contact_stiffness.hpp"
#include "contact/dem_law.hpp"

namespace ckpd {

namespace {

bool intact_bond(const void* context, std::uint32_t i, std::uint32_t j) {
  return joined_by_intact_bond(*static_cast<const Body*>(context), i, j);
}

}  // namespace

// Families are sorted by neighbour index: a binary search over i's row.
bool joined_by_intact_bond(const Body& body, std::uint32_t i, std::uint32_t j) {
  const auto begin = body.family.neighbour.begin();
  const auto first = begin + static_cast<std::ptrdiff_t>(body.family.offset[i]);
  const auto last = begin + static_cast<std::ptrdiff_t>(body.family.offset[i + 1]);
  const auto it = std::lower_bound(first, last, j);
  return it != last && *it == j && body.bond_intact[static_cast<std::size_t>(it - begin)];
}

ContactBody contact_body(const SceneBody& sb, PointSet points) {
  return {points,        sb.rigid.has_value(), sb.rigid.has_value() && sb.rigid->prescribed(),
          sb.wall.get(), sb.elastic,           sb.sphere_radius};
}

PointSet point_set(const SceneBody& sb) {
  const Body& body = sb.body;
  PointSet p;
  p.name = body.name;
  p.dimension = body.dimension;
  p.density = body.density;
  p.horizon = body.horizon;
  p.spacing = sb.spacing;
  p.reference = body.reference_position;
  p.displacement = body.displacement;
  p.velocity = body.velocity;
  p.volume = body.volume;
  if (!body.family.offset.empty() && body.family.offset.back() > 0) {
    p.bonds = {&body, intact_bond};
    if (!sb.rigid) {
      p.family_offset = body.family.offset;
      p.family_neighbour = body.family.neighbour;
      p.bond_intact = body.bond_intact;
    }
  }
  if (sb.rigid) {
    p.spins = true;
    p.angular_velocity = sb.rigid->angular_velocity();
    p.rigid_mass =
        sb.rigid->prescribed() ? std::numeric_limits<double>::infinity() : sb.rigid->mass();
  }
  return p;
}

PointSet point_set(SceneBody& sb) {
  PointSet p = point_set(std::as_const(sb));
  p.force_density = sb.body.force_density;
  if (sb.rigid && !sb.rigid->prescribed()) p.couple = sb.rigid->couple();
  return p;
}

std::vector<ContactBody> contact_bodies(Scene& scene) {
  std::vector<ContactBody> bodies;
  for (SceneBody& sb : scene.bodies) bodies.push_back(contact_body(sb, point_set(sb)));
  return bodies;
}

std::vector<ContactBody> contact_bodies(const Scene& scene) {
  std::vector<ContactBody> bodies;
  for (const SceneBody& sb : scene.bodies) bodies.push_back(contact_body(sb, point_set(sb)));
  return bodies;
}

std::vector<PointSet> contact_point_sets(Scene& scene) {
  std::vector<PointSet> points;
  contact_point_sets(scene, points);
  return points;
}

void contact_point_sets(Scene& scene, std::vector<PointSet>& points) {
  points.clear();
  for (SceneBody& sb : scene.bodies) points.push_back(point_set(sb));
}

std::vector<ContactLawNote> contact_law_notes(const Scene& scene) {
  std::vector<ContactLawNote> notes;
  if (!scene.contact.present) return notes;
  const std::vector<ContactBody> bodies = contact_bodies(scene);
  for (std::size_t a = 0; a < bodies.size(); ++a)
    for (std::size_t b = a; b < bodies.size(); ++b)
      if (const std::optional<PairLaw> law = scene.contact.law(bodies, a, b))
        notes.push_back(
            {std::string(bodies[a].points.name) + "/" + std::string(bodies[b].points.name),
             law->name, law->dem ? law->dem->friction : 0.0,
             law->dem ? law->dem->damping_ratio() : 0.0});
  return notes;
}

std::string contact_law_report(const Scene& scene) {
  std::ostringstream s;
  for (const ContactLawNote& n : contact_law_notes(scene))
    if (n.law != kDefaultLaw)
      s << "  contact " << n.bodies << ": law " << n.law << ", friction " << n.friction
        << ", normal damping ratio " << n.damping_ratio << '\n';
  return s.str();
}

bool has_contact_work(const Scene& scene) {
  if (!scene.contact.present) return false;
  const std::vector<ContactBody> bodies = contact_bodies(scene);
  for (std::size_t a = 0; a < bodies.size(); ++a)
    for (std::size_t b = a; b < bodies.size(); ++b)
      if (scene.contact.law(bodies, a, b)) return true;
  return false;
}

std::unique_ptr<ContactManager> make_contact_manager(Scene& scene) {
  if (!has_contact_work(scene)) return nullptr;
  return std::make_unique<ContactManager>(contact_bodies(scene), scene.contact);
}

std::vector<double> contact_stiffness_bounds(const Scene& scene) {
  return contact_stiffness_bounds(scene.contact, contact_bodies(scene));
}

StableStep stable_step_with(const Body& body, double extra_stiffness) {
  StableStep s;
  for (std::size_t i = 0; i < body.size(); ++i) {
    const double k = body.stiffness_bound[i] + extra_stiffness;
    if (k <= 0) continue;
    const double dt = 2.0 * std::sqrt(body.density / k);
    if (dt < s.dt) s = {dt, i};
  }
  return s;
}

}  // namespace ckpd
