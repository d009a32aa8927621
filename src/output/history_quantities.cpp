#include "src/output/history_quantities.hpp"

#include "bodies/fragments.hpp"
#include "src/input/nearest_name.hpp"

namespace ckpd {

namespace {

const SceneBody& body_at(const Simulation& sim, const HistoryQuantity& q, std::size_t k = 0) {
  return sim.whole_scene().bodies[q.bodies[k]];
}

void put(std::vector<double>& out, const Vec3& v) {
  out = {v.x(), v.y(), v.z()};
}

Vec3 momentum(const Body& b) {
  Vec3 p = Vec3::Zero();
  for (std::size_t i = 0; i < b.size(); ++i) p += b.density * b.volume[i] * b.velocity[i];
  return p;
}

using Compute =
    std::function<void(const Simulation&, const HistoryQuantity&, std::vector<double>&)>;

HistoryQuantityKind vector_kind(std::string name, int bodies, bool region, Compute c) {
  return {std::move(name), bodies, region, {"x", "y", "z"}, std::move(c)};
}
HistoryQuantityKind scalar_kind(std::string name, int bodies, Compute c) {
  return {std::move(name), bodies, false, {""}, std::move(c)};
}

std::vector<HistoryQuantityKind> make_table() {
  std::vector<HistoryQuantityKind> t;
  t.push_back(
      vector_kind("momentum", 1, false,
                  [](const Simulation& sim, const HistoryQuantity& q, std::vector<double>& out) {
                    put(out, momentum(body_at(sim, q).body));
                  }));
  t.push_back(
      vector_kind("centre_of_mass", 1, false,
                  [](const Simulation& sim, const HistoryQuantity& q, std::vector<double>& out) {
                    // One density per body: volume weights are mass weights.
                    const Body& b = body_at(sim, q).body;
                    Vec3 m_x = Vec3::Zero();
                    double m = 0;
                    for (std::size_t i = 0; i < b.size(); ++i) {
                      m_x += b.volume[i] * b.current_position(i);
                      m += b.volume[i];
                    }
                    put(out, m_x / m);
                  }));
  t.push_back(
      vector_kind("mean_velocity", 1, false,
                  [](const Simulation& sim, const HistoryQuantity& q, std::vector<double>& out) {
                    const Body& b = body_at(sim, q).body;
                    put(out, momentum(b) / b.mass());
                  }));
  t.push_back(
      scalar_kind("kinetic_energy", 1,
                  [](const Simulation& sim, const HistoryQuantity& q, std::vector<double>& out) {
                    const Body& b = body_at(sim, q).body;
                    double k = 0;
                    for (std::size_t i = 0; i < b.size(); ++i)
                      k += 0.5 * b.density * b.volume[i] * b.velocity[i].squaredNorm();
                    out = {k};
                  }));
  t.push_back(
      scalar_kind("strain_energy", 1,
                  [](const Simulation& sim, const HistoryQuantity& q, std::vector<double>& out) {
                    const SceneBody& sb = body_at(sim, q);
                    double w = 0;
                    if (!sb.rigid)
                      for (std::size_t i = 0; i < sb.body.size(); ++i)
                        w += sb.body.volume[i] * sb.body.strain_energy_density[i];
                    out = {w};
                  }));
  t.push_back(
      scalar_kind("broken_bonds", 1,
                  [](const Simulation& sim, const HistoryQuantity& q, std::vector<double>& out) {
                    out = {static_cast<double>(sim.broken_bonds(q.bodies[0]))};
                  }));
  t.push_back(
      scalar_kind("fragments", 1,
                  [](const Simulation& sim, const HistoryQuantity& q, std::vector<double>& out) {
                    const SceneBody& sb = body_at(sim, q);
                    out = {sb.rigid ? 1.0 : static_cast<double>(find_fragments(sb.body).count())};
                  }));
  t.push_back(
      vector_kind("reaction_force", 1, true,
                  [](const Simulation& sim, const HistoryQuantity& q, std::vector<double>& out) {
                    const Body& b = body_at(sim, q).body;
                    Vec3 r = Vec3::Zero();
                    for (std::uint32_t i : q.points)
                      r += b.volume[i] * (b.density * b.acceleration[i] - b.force_density[i]);
                    put(out, r);
                  }));
  t.push_back(
      vector_kind("contact_force", 2, false,
                  [](const Simulation& sim, const HistoryQuantity& q, std::vector<double>& out) {
                    const Body& b = body_at(sim, q).body;
                    Vec3 f = Vec3::Zero();
                    for (std::size_t i = 0; i < b.size(); ++i)
                      f += b.volume[i] * (b.force_density[i] - b.external_force_density[i]);
                    put(out, f);
                  }));
  t.push_back(scalar_kind("contact_energy", 2,
                          [](const Simulation& sim, const HistoryQuantity&,
                             std::vector<double>& out) { out = {sim.energies().contact}; }));
  return t;
}

}  // namespace

const std::vector<HistoryQuantityKind>& history_quantity_table() {
  static const std::vector<HistoryQuantityKind> table = make_table();
  return table;
}

const HistoryQuantityKind* find_history_quantity(const std::string& name) {
  return find_row(history_quantity_table(), name);
}

std::string known_history_quantities() {
  return join_names(row_names(history_quantity_table()));
}

std::string history_quantity_problem(const Scene& scene, const HistoryQuantity& q) {
  if (q.quantity != "contact_force" && q.quantity != "contact_energy") return "";
  const std::size_t a = q.bodies[0], b = q.bodies[1];
  const auto name = [&](std::size_t k) { return "'" + scene.bodies[k].body.name + "'"; };
  if (a == b) return "two different bodies";
  bool pair = false;
  std::string others;
  std::size_t distinct_pairs = 0;
  for (const ContactPairRadius& p : contact_pair_radii(scene)) {
    if (p.a == p.b) {
      if (q.quantity == "contact_energy")
        return "the only contact in the scene (body " + name(p.a) +
               " has self-contact, whose energy the contact library sums with the pair's)";
      continue;
    }
    ++distinct_pairs;
    if ((p.a == a && p.b == b) || (p.a == b && p.b == a)) {
      pair = true;
    } else if (p.a == a || p.b == a) {
      others += (others.empty() ? "" : ", ") + name(p.a == a ? p.b : p.a);
    }
  }
  if (!pair)
    return "two bodies in contact (" + name(a) + " and " + name(b) + " have no contact law)";
  if (q.quantity == "contact_force" && !others.empty())
    return "a first body that touches only the second (" + name(a) + " is also in contact with " +
           others + "; its contact force would be the sum over them)";
  if (q.quantity == "contact_energy" && distinct_pairs > 1)
    return "the scene's only contact pair (the contact library sums the energy over its " +
           std::to_string(distinct_pairs) + " pairs)";
  return "";
}

std::vector<std::string> history_columns(const HistoryQuantity& q) {
  std::vector<std::string> out;
  for (const std::string& suffix : find_history_quantity(q.quantity)->columns)
    out.push_back(suffix.empty() ? q.label : q.label + "_" + suffix);
  return out;
}

std::vector<double> history_values(const Simulation& sim, const HistoryQuantity& q) {
  std::vector<double> out;
  find_history_quantity(q.quantity)->compute(sim, q, out);
  return out;
}

}  // namespace ckpd
