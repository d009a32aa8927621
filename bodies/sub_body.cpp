#include "bodies/sub_body.hpp"

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>

#include "bodies/force_model.hpp"
#include "bodies/lattice_stencil.hpp"
#include "bodies/upper_bonds.hpp"

namespace ckpd {

std::vector<std::uint32_t> core_and_halo(const Body& body, const std::vector<std::uint8_t>& core) {
  const std::size_t n = body.size();
  if (core.size() != n)
    throw std::invalid_argument("core_and_halo: " + std::to_string(core.size()) +
                                " core flags for a body of " + std::to_string(n) + " points");
  std::vector<std::uint8_t> keep(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (core[i] == 0) continue;
    keep[i] = 1;
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k)
      keep[body.family.neighbour[k]] = 1;
  }
  std::vector<std::uint32_t> points;
  for (std::size_t i = 0; i < n; ++i)
    if (keep[i] != 0) points.push_back(static_cast<std::uint32_t>(i));
  return points;
}

namespace {

template <class T>
std::vector<T> gather(const std::vector<T>& v, const std::vector<std::uint32_t>& points) {
  std::vector<T> out;
  if (v.empty()) return out;  // optional per-point data (no_failure, owned_centres)
  out.reserve(points.size());
  for (const std::uint32_t p : points) out.push_back(v[p]);
  return out;
}

}  // namespace

BodyRestriction restrict_body(const Body& body, const std::vector<std::uint32_t>& points) {
  const std::size_t n = body.size();
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (points[k] >= n || (k > 0 && points[k] <= points[k - 1]))
      throw std::invalid_argument("restrict_body: body '" + body.name +
                                  "': the points must be strictly increasing indices below " +
                                  std::to_string(n) + " (entry " + std::to_string(k) + " is " +
                                  std::to_string(points[k]) + ")");
  }
  if (force_model(body).prepare != nullptr)
    throw std::invalid_argument("restrict_body: body '" + body.name +
                                "': its force model keeps per-point data of its own (the "
                                "state-based solid); it cannot be restricted to some points");
  BodyRestriction r;
  r.global = points;
  Body& s = r.body;
  s.name = body.name;
  s.dimension = body.dimension;
  s.density = body.density;
  s.horizon = body.horizon;
  s.constants = body.constants;
  s.critical_stretch = body.critical_stretch;
  s.damage_enabled = body.damage_enabled;
  s.degenerate_fraction = body.degenerate_fraction;
  s.inversion_penalty = body.inversion_penalty;
  s.damage_rule = body.damage_rule;
  s.model = body.model;
  s.strain_measure = body.strain_measure;
  s.state_based = body.state_based;
  s.force_form = body.force_form;
  s.beta_cap = body.beta_cap;
  s.beta_capped_points = body.beta_capped_points;
  s.beta_max_raw = body.beta_max_raw;
  s.screens = body.screens;
  s.stencil_note = body.stencil_note;

  s.reference_position = gather(body.reference_position, points);
  s.volume = gather(body.volume, points);
  s.beta = gather(body.beta, points);
  s.dv1 = gather(body.dv1, points);
  s.dv2 = gather(body.dv2, points);
  s.dv3 = gather(body.dv3, points);
  s.n2 = gather(body.n2, points);
  s.n3 = gather(body.n3, points);
  s.stiffness_bound = gather(body.stiffness_bound, points);
  s.no_failure = gather(body.no_failure, points);
  s.displacement = gather(body.displacement, points);
  s.velocity = gather(body.velocity, points);
  s.acceleration = gather(body.acceleration, points);
  s.external_force_density = gather(body.external_force_density, points);
  s.force_density = gather(body.force_density, points);
  s.strain_energy_density = gather(body.strain_energy_density, points);
  s.owned_centres = gather(body.owned_centres, points);
  s.booked_points = gather(body.booked_points, points);

  // The bonds among the kept points, in the whole body's order (rows stay sorted: the local
  // numbering is monotone), each with its flag.
  constexpr std::uint32_t kDropped = ~std::uint32_t{0};
  std::vector<std::uint32_t> local(n, kDropped);
  for (std::size_t k = 0; k < points.size(); ++k) local[points[k]] = static_cast<std::uint32_t>(k);
  s.family.offset.assign(points.size() + 1, 0);
  for (std::size_t k = 0; k < points.size(); ++k) {
    const std::size_t i = points[k];
    for (std::size_t e = body.family.offset[i]; e < body.family.offset[i + 1]; ++e) {
      const std::uint32_t j = local[body.family.neighbour[e]];
      if (j == kDropped) continue;
      s.family.neighbour.push_back(j);
      s.bond_intact.push_back(body.bond_intact[e]);
    }
    s.family.offset[k + 1] = s.family.neighbour.size();
  }

  if (body.stencil) {
    // The tables are the body's (they describe lattice offsets, not points); only the per-point
    // lattice coordinates follow the kept points.
    auto stencil = std::make_shared<LatticeStencil>(*body.stencil);
    stencil->coord.clear();
    stencil->coord.reserve(3 * points.size());
    for (const std::uint32_t p : points)
      for (int c = 0; c < 3; ++c) stencil->coord.push_back(body.stencil->coord[3 * p + c]);
    s.stencil = std::move(stencil);
  }
  if (body.upper_bonds) s.upper_bonds = build_upper_bonds(s.reference_position, s.family);
  if (body.upper_rows) s.upper_rows = build_upper_rows(s);
  return r;
}

}  // namespace ckpd
