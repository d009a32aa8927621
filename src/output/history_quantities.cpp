#include "src/output/history_quantities.hpp"

#include <algorithm>

#include "bodies/fragments.hpp"
#include "src/engine/distribution.hpp"
#include "src/engine/ranks.hpp"
#include "src/input/nearest_name.hpp"

namespace ckpd {

namespace {

// Calls visit(i) for every point of body b that this source books (all of a whole body's).
template <class Visit>
void for_booked(const HistorySource& src, std::size_t b, Visit&& visit) {
  const Body& body = src.scene.bodies[b].body;
  for (std::size_t i = 0; i < body.size(); ++i)
    if (body.books(i)) visit(body, i);
}

void add3(double* sums, const Vec3& v) {
  for (int k = 0; k < 3; ++k) sums[k] += v[k];
}

// sums[0..2] += the booked points' momentum; with `mass`, sums[3] += their mass.
void add_momentum(const HistorySource& src, std::size_t body, double* sums, bool mass) {
  for_booked(src, body, [&](const Body& b, std::size_t i) {
    add3(sums, b.density * b.volume[i] * b.velocity[i]);
    if (mass) sums[3] += b.density * b.volume[i];
  });
}

using Add = std::function<void(const HistorySource&, const HistoryQuantity&, double*)>;
using Finish = std::function<void(const double*, double*)>;

HistoryQuantityKind vector_kind(std::string name, int bodies, bool region, std::size_t sums,
                                Add add, Finish finish = nullptr) {
  return {std::move(name), bodies, region,         {"x", "y", "z"},
          false,           sums,   std::move(add), std::move(finish)};
}
HistoryQuantityKind scalar_kind(std::string name, int bodies, Add add, bool whole = false) {
  return {std::move(name), bodies, false, {""}, whole, 1, std::move(add), nullptr};
}

// A vector over a scalar: sums (x, y, z, w) -> (x, y, z) / w.
void divide_by_last(const double* sums, double* columns) {
  for (int k = 0; k < 3; ++k) columns[k] = sums[k] / sums[3];
}

std::vector<HistoryQuantityKind> make_table() {
  std::vector<HistoryQuantityKind> t;
  t.push_back(vector_kind("momentum", 1, false, 3,
                          [](const HistorySource& src, const HistoryQuantity& q, double* sums) {
                            add_momentum(src, q.bodies[0], sums, false);
                          }));
  // One density per body: volume weights are mass weights.
  t.push_back(vector_kind(
      "centre_of_mass", 1, false, 4,
      [](const HistorySource& src, const HistoryQuantity& q, double* sums) {
        for_booked(src, q.bodies[0], [&](const Body& b, std::size_t i) {
          add3(sums, b.volume[i] * b.current_position(i));
          sums[3] += b.volume[i];
        });
      },
      divide_by_last));
  t.push_back(vector_kind(
      "mean_velocity", 1, false, 4,
      [](const HistorySource& src, const HistoryQuantity& q, double* sums) {
        add_momentum(src, q.bodies[0], sums, true);
      },
      divide_by_last));
  t.push_back(scalar_kind(
      "kinetic_energy", 1, [](const HistorySource& src, const HistoryQuantity& q, double* sums) {
        for_booked(src, q.bodies[0], [&](const Body& b, std::size_t i) {
          sums[0] += 0.5 * b.density * b.volume[i] * b.velocity[i].squaredNorm();
        });
        // A DEM sphere's spin, booked with its one point.
        const SceneBody& sb = src.scene.bodies[q.bodies[0]];
        if (sb.rigid && sb.body.size() > 0 && sb.body.books(0))
          sums[0] += sb.rigid->spin_energy_beyond_points();
      }));
  t.push_back(scalar_kind("strain_energy", 1,
                          [](const HistorySource& src, const HistoryQuantity& q, double* sums) {
                            if (src.scene.bodies[q.bodies[0]].rigid) return;
                            for_booked(src, q.bodies[0], [&](const Body& b, std::size_t i) {
                              sums[0] += b.volume[i] * b.strain_energy_density[i];
                            });
                          }));
  t.push_back(scalar_kind("broken_bonds", 1,
                          [](const HistorySource& src, const HistoryQuantity& q, double* sums) {
                            // Already over all ranks.
                            if (src.root)
                              sums[0] = static_cast<double>(src.sim.broken_bonds(q.bodies[0]));
                          }));
  t.push_back(scalar_kind(
      "fragments", 1,
      [](const HistorySource& src, const HistoryQuantity& q, double* sums) {
        const SceneBody& sb = src.scene.bodies[q.bodies[0]];
        sums[0] = sb.rigid ? 1.0 : static_cast<double>(find_fragments(sb.body).count());
      },
      true));
  t.push_back(vector_kind(
      "reaction_force", 1, true, 3,
      [](const HistorySource& src, const HistoryQuantity& q, double* sums) {
        const std::size_t index = q.bodies[0];
        const Body& b = src.scene.bodies[index].body;
        const auto reaction = [&](std::size_t i) {
          add3(sums, b.volume[i] * (b.density * b.acceleration[i] - b.force_density[i]));
        };
        if (!src.distribution) {
          for (std::uint32_t i : q.points) reaction(i);
          return;
        }
        // A rank's part: the region's points it books, found by their whole-body index.
        const std::vector<std::uint32_t>& whole = src.distribution->body(index).links.points;
        for (std::uint32_t g : q.points) {
          const auto at = std::lower_bound(whole.begin(), whole.end(), g);
          if (at == whole.end() || *at != g) continue;
          const auto i = static_cast<std::size_t>(at - whole.begin());
          if (b.books(i)) reaction(i);
        }
      }));
  t.push_back(vector_kind("contact_force", 2, false, 3,
                          [](const HistorySource& src, const HistoryQuantity& q, double* sums) {
                            for_booked(src, q.bodies[0], [&](const Body& b, std::size_t i) {
                              add3(sums, b.volume[i] *
                                             (b.force_density[i] - b.external_force_density[i]));
                            });
                          }));
  t.push_back(scalar_kind("contact_energy", 2,
                          [](const HistorySource& src, const HistoryQuantity&, double* sums) {
                            if (src.root) sums[0] = src.sim.energies().contact;  // over all ranks
                          }));
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

bool history_needs_whole_scene(const std::vector<HistoryQuantity>& chosen) {
  return std::any_of(chosen.begin(), chosen.end(), [](const HistoryQuantity& q) {
    return find_history_quantity(q.quantity)->whole;
  });
}

std::vector<double> history_values(const Simulation& sim,
                                   const std::vector<HistoryQuantity>& chosen) {
  const Distribution* d = sim.distribution();
  const HistorySource mine{sim, d ? sim.scene() : sim.whole_scene(), d, ranks::root()};
  const HistorySource whole{sim, sim.whole_scene(), nullptr, true};
  std::vector<double> sums;
  for (const HistoryQuantity& q : chosen) {
    const HistoryQuantityKind& kind = *find_history_quantity(q.quantity);
    const std::size_t at = sums.size();
    sums.resize(at + kind.sums, 0.0);
    if (!kind.whole)
      kind.add(mine, q, sums.data() + at);
    else if (mine.root)  // rank 0's whole scene, gathered; the other ranks add nothing
      kind.add(whole, q, sums.data() + at);
  }
  if (d) {
    std::vector<double> scratch;
    ranks::sum_in_rank_order(sums, scratch);
  }
  std::vector<double> out;
  std::size_t at = 0;
  for (const HistoryQuantity& q : chosen) {
    const HistoryQuantityKind& kind = *find_history_quantity(q.quantity);
    const std::size_t columns = kind.columns.size();
    out.resize(out.size() + columns);
    if (kind.finish)
      kind.finish(sums.data() + at, out.data() + out.size() - columns);
    else
      std::copy(sums.begin() + static_cast<std::ptrdiff_t>(at),
                sums.begin() + static_cast<std::ptrdiff_t>(at + columns), out.end() - columns);
    at += kind.sums;
  }
  return out;
}

}  // namespace ckpd
