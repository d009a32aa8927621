#include "src/engine/scene_warnings.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "contact/contact_law.hpp"
#include "src/engine/contact_coupling.hpp"
#include "src/engine/simulation.hpp"

namespace ckpd {

namespace {

struct Motion {
  Vec3 lo, hi;    // bounding box of the current positions, m
  Vec3 centre;    // volume-weighted centre, m
  Vec3 velocity;  // volume-weighted mean velocity, m/s
};

Motion motion_of(const Body& b) {
  Motion m{Vec3::Constant(std::numeric_limits<double>::infinity()),
           Vec3::Constant(-std::numeric_limits<double>::infinity()), Vec3::Zero(), Vec3::Zero()};
  double volume = 0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    const Vec3 x = b.current_position(i);
    m.lo = m.lo.cwiseMin(x);
    m.hi = m.hi.cwiseMax(x);
    m.centre += b.volume[i] * x;
    m.velocity += b.volume[i] * b.velocity[i];
    volume += b.volume[i];
  }
  if (volume > 0) {
    m.centre /= volume;
    m.velocity /= volume;
  }
  return m;
}

// Distance between two axis-aligned boxes (0 when they touch or overlap).
double box_gap(const Motion& a, const Motion& b) {
  const Vec3 gap = (a.lo - b.hi).cwiseMax(b.lo - a.hi).cwiseMax(Vec3::Zero());
  return gap.norm();
}

std::string quoted(const std::string& name) {
  return "'" + name + "'";
}

// Why no contact acts between bodies a and b: the case has no `contact` section, or no law
// applies to the pair. Empty when the pair was switched off on purpose (enabled: false).
std::string missing_contact(const Scene& scene, std::size_t a, std::size_t b) {
  if (!scene.contact.present) return "the case has no `contact` section";
  if (const ContactPairSetting* own = scene.contact.pair_setting(a, b); own && !own->enabled)
    return "";
  return "no contact law applies to the pair (no `stiffness`, globally or for the pair)";
}

void closing_bodies(const Simulation& sim, double duration, std::vector<std::string>& out) {
  const Scene& scene = sim.whole_scene();
  const std::vector<ContactBody> bodies = contact_bodies(scene);
  std::vector<Motion> motion;
  for (const SceneBody& sb : scene.bodies) motion.push_back(motion_of(sb.body));
  for (std::size_t a = 0; a < bodies.size(); ++a)
    for (std::size_t b = a + 1; b < bodies.size(); ++b) {
      if (bodies[a].wall || bodies[b].wall) continue;  // a wall's points are not its surface
      if (bodies[a].prescribed && bodies[b].prescribed) continue;
      if (scene.contact.present && scene.contact.law(bodies, a, b)) continue;
      const Vec3 towards = motion[b].centre - motion[a].centre;
      const Vec3 relative = motion[b].velocity - motion[a].velocity;
      const double closing = towards.norm() > 0 ? -relative.dot(towards) / towards.norm() : 0;
      const double gap = box_gap(motion[a], motion[b]);
      // Closing, and near enough to meet within the run at the speed they close with.
      if (!(closing > 0) || gap > closing * duration) continue;
      const std::string why = missing_contact(scene, a, b);
      if (why.empty()) continue;
      std::ostringstream s;
      s << "bodies " << quoted(scene.bodies[a].body.name) << " and "
        << quoted(scene.bodies[b].body.name) << " close on each other at " << closing
        << " m/s from " << gap << " m apart, but " << why
        << ": they will pass through each other (add `contact: {stiffness: ...}`, "
           "docs/CONTACT_LAWS.md)";
      out.push_back(s.str());
    }
}

void non_conserving_contact(const Scene& scene, std::vector<std::string>& out) {
  if (!scene.contact.present) return;
  const std::vector<ContactBody> bodies = contact_bodies(scene);
  for (std::size_t a = 0; a < bodies.size(); ++a)
    for (std::size_t b = a; b < bodies.size(); ++b) {
      const std::optional<PairLaw> law = scene.contact.law(bodies, a, b);
      if (!law || law->name != kOwnHorizonLaw) continue;
      std::ostringstream s;
      s << "contact " << quoted(std::string(bodies[a].points.name)) << "/"
        << quoted(std::string(bodies[b].points.name)) << " uses `" << kOwnHorizonLaw
        << "`, the seed's rule (each body its own horizon in 9 Ccon/(pi delta^5)): it does not "
           "conserve momentum or energy";
      if (law->coefficient[0] != law->coefficient[1])
        s << " (here the two sides' coefficients differ by the factor "
          << std::max(law->coefficient[0], law->coefficient[1]) /
                 std::min(law->coefficient[0], law->coefficient[1])
          << ")";
      else
        s << " between bodies of different horizons (here the two are equal)";
      s << "; the default `repulsive` uses one pair coefficient and conserves both; use this "
           "rule only to reproduce the seed";
      out.push_back(s.str());
    }
}

// Whether bonds of the body can fail during the run (a pre-cracked body has damage bookkeeping
// even without a failure criterion: its cut bonds must carry no force).
bool can_break(const Body& b) {
  return b.damage_enabled &&
         (std::isfinite(b.critical_stretch) || std::isfinite(b.state_based.failure_beta));
}

// Pre-cracks on a body that cannot break, or a damage field in a case where no body can: the
// author probably forgot `fracture_energy`. (One unbreakable body among breakable ones, a
// projectile say, is left alone.)
void unbreakable_bodies(const Simulation& sim, std::vector<std::string>& out) {
  const Scene& scene = sim.whole_scene();
  bool any_breakable = false;
  bool any_deformable = false;
  for (const SceneBody& sb : scene.bodies) {
    if (sb.rigid) continue;
    any_breakable = any_breakable || can_break(sb.body);
    any_deformable = true;
  }
  for (std::size_t k = 0; k < scene.bodies.size(); ++k) {
    const SceneBody& sb = scene.bodies[k];
    if (sb.rigid || can_break(sb.body) || sim.precracked_bonds(k) == 0) continue;
    out.push_back("body " + quoted(sb.body.name) + " has pre-cracks (" +
                  std::to_string(sim.precracked_bonds(k)) +
                  " bonds start failed) but cannot break further: its material has no "
                  "`fracture_energy` (J/m^2); give it one if the cracks are meant to grow");
  }
  const bool damage_field = std::find(scene.output.fields.begin(), scene.output.fields.end(),
                                      "damage") != scene.output.fields.end();
  if (damage_field && !any_breakable && any_deformable)
    out.push_back(
        "the case writes the damage field, but no body can break: no material has a "
        "`fracture_energy` (J/m^2)");
}

void three_neighbour_cost(const Scene& scene, std::vector<std::string>& out) {
  for (const SceneBody& sb : scene.bodies) {
    const Body& b = sb.body;
    if (sb.rigid || b.dimension != 3 || b.constants.c3 == 0) continue;
    std::ostringstream s;
    const double bonds = static_cast<double>(std::max<std::size_t>(b.bond_count(), 1));
    s << "body " << quoted(b.name)
      << ": a Poisson ratio other than 1/4 makes C3 = " << b.constants.c3
      << " non-zero, so every point carries three-neighbour interactions ("
      << static_cast<double>(b.total_three_neighbour()) / bonds
      << " ordered tetrahedra per bond); a step costs 10-40 times one at nu = 1/4 (bonds only, "
         "measured: docs/PERFORMANCE.md)";
    if (b.constants.c3 < 0)
      s << ". nu < 1/4 gives C3 < 0: a tetrahedron's volume change lowers the energy, held up "
           "only by the bonds (strain measures with m <= 0 are refused for it, THEORY.md "
           "section 2)";
    out.push_back(s.str());
  }
}

// A pulse of N steps (t1 = N dt) is sampled at t = k dt: its impulse comes out as
// (2/3) p0 t1 (1 - 1/N^2), and a velocity held for N steps ends within one step of its
// `duration`. Below 10 steps that is more than 1 %.
void short_durations(const Simulation& sim, std::vector<std::string>& out) {
  const double dt = sim.step_choice().dt;
  for (const SceneBody& sb : sim.whole_scene().bodies)
    for (const auto& c : sb.conditions) {
      const double steps = c->duration() / dt;
      if (!(steps < 10)) continue;
      std::ostringstream s;
      s << c->duration_where() << ": " << c->duration() << " s on body " << quoted(sb.body.name)
        << " lasts " << steps << " time steps (dt = " << dt
        << " s): a pulse's impulse is resolved to about 1/N^2 = " << 100.0 / (steps * steps)
        << " %, a held velocity's end to one step, 1/N = " << 100.0 / steps
        << " %; a smaller time.dt resolves it better";
      out.push_back(s.str());
    }
}

}  // namespace

std::vector<std::string> scene_warnings(const Simulation& sim) {
  const Scene& scene = sim.whole_scene();
  const double duration = std::isfinite(scene.time.end_time)
                              ? scene.time.end_time
                              : static_cast<double>(sim.planned_steps()) * sim.step_choice().dt;
  std::vector<std::string> out;
  closing_bodies(sim, duration, out);
  non_conserving_contact(scene, out);
  unbreakable_bodies(sim, out);
  three_neighbour_cost(scene, out);
  short_durations(sim, out);
  return out;
}

}  // namespace ckpd
