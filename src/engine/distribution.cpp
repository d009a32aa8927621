#include "src/engine/distribution.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "bodies/damage.hpp"
#include "bodies/state_based_model.hpp"
#include "bodies/sub_body.hpp"
#include "src/engine/contact_coupling.hpp"
#include "src/engine/ranks.hpp"

namespace ckpd {

namespace {

// Per owned point in a gather: displacement, velocity, acceleration, force density, external
// force density (3 each) and the strain energy density; then the point's bond flags, one byte
// each.
constexpr std::size_t kGatheredValues = 16;

void put(std::vector<unsigned char>& bytes, const double* values, std::size_t count) {
  const std::size_t at = bytes.size();
  bytes.resize(at + count * sizeof(double));
  std::memcpy(bytes.data() + at, values, count * sizeof(double));
}

// A rigid body's state, from one whole copy to another.
void copy_rigid_body(const SceneBody& from, SceneBody& to) {
  Body& b = to.body;
  b.displacement = from.body.displacement;
  b.velocity = from.body.velocity;
  b.acceleration = from.body.acceleration;
  b.force_density = from.body.force_density;
  b.external_force_density = from.body.external_force_density;
  b.strain_energy_density = from.body.strain_energy_density;
  to.rigid->restore(from.rigid->state());
}

}  // namespace

std::string distribution_refusal(const Scene& scene) {
  if (scene.time.adaptive_step) return "time.step_mode is adaptive";
  for (const SceneBody& sb : scene.bodies) {
    const std::string who = "body '" + sb.body.name + "' ";
    if (sb.far_field) return who + "has a far field";
    if (sb.body.model == &state_based_kernels()) return who + "is a state-based solid";
    if (stiffens_in_compression(sb.body))
      return who + "has a strain measure that stiffens in compression (m <= 0)";
  }
  // Contact is taken under the seed law and DEM laws without friction (contact_ghosts.hpp).
  if (scene.contact.present) {
    const std::vector<ContactBody> bodies = contact_bodies(scene);
    for (std::size_t a = 0; a < bodies.size(); ++a)
      for (std::size_t b = a; b < bodies.size(); ++b)
        if (const std::optional<PairLaw> law = scene.contact.law(bodies, a, b);
            law && law->dem && law->dem->friction > 0)
          return "the contact of bodies '" + std::string(bodies[a].points.name) + "' and '" +
                 std::string(bodies[b].points.name) + "' has friction (the DEM law " + law->name +
                 "'s tangential springs are not distributed)";
  }
  return {};
}

DistributedScene distribute_scene(Scene& whole, int rank, int ranks) {
  const std::string refusal = distribution_refusal(whole);
  if (!refusal.empty())
    throw std::invalid_argument("distributed memory does not take this scene: " + refusal);
  DistributedScene out;
  out.distribution = std::make_unique<Distribution>();
  Distribution& d = *out.distribution;
  d.rank_ = rank;
  d.ranks_ = ranks;
  d.step_choice_ = choose_time_step(whole);
  d.contact_stiffness_ = contact_stiffness_bounds(whole);
  std::vector<const Body*> bodies;
  std::vector<bool> rigid;
  for (const SceneBody& sb : whole.bodies) {
    bodies.push_back(&sb.body);
    rigid.push_back(sb.rigid.has_value());
  }
  d.decomposition_ = decompose(bodies, rigid, ranks);
  Scene& local = out.local;
  local.case_file = whole.case_file;
  local.fingerprint = whole.fingerprint;
  local.physics = whole.physics;
  local.contact = whole.contact;
  local.time = whole.time;
  local.output = whole.output;
  for (std::size_t b = 0; b < whole.bodies.size(); ++b) {
    SceneBody& w = whole.bodies[b];
    DistributedBody db;
    db.whole_points = w.body.size();
    if (w.rigid) {
      // Whole on every rank; its points are every rank's to move, rank 0's to book.
      db.replicated = true;
      db.links.points.resize(w.body.size());
      for (std::size_t i = 0; i < w.body.size(); ++i)
        db.links.points[i] = static_cast<std::uint32_t>(i);
      db.links.owned.assign(w.body.size(), 1);
      d.initially_failed_.push_back(0);
      SceneBody l;
      l.body = w.body;
      if (rank != 0) l.body.booked_points.assign(w.body.size(), 0);
      l.spacing = w.spacing;
      l.rigid = w.rigid;
      l.wall = w.wall;
      l.wall_surface = w.wall_surface;
      l.mesh = w.mesh;
      l.elastic = w.elastic;
      l.sphere_radius = w.sphere_radius;
      l.conditions = std::move(w.conditions);
      w.conditions.clear();
      local.bodies.push_back(std::move(l));
      d.bodies_.push_back(std::move(db));
      continue;
    }
    db.links = halo_links(w.body, d.decomposition_.owner[b], rank, ranks);
    if (rank == 0) db.owner = d.decomposition_.owner[b];
    // omega_max dx bounds the fastest wave a lattice carries (Simulation's speed limit).
    const double k =
        *std::max_element(w.body.stiffness_bound.begin(), w.body.stiffness_bound.end());
    d.wave_speed_ = std::max(d.wave_speed_, w.spacing * std::sqrt(k / w.body.density));
    d.initially_failed_.push_back(failed_bond_count(w.body));
    SceneBody l;
    l.body = restrict_body(w.body, db.links.points).body;
    l.body.owned_centres = db.links.owned;
    l.body.booked_points = db.links.owned;
    l.spacing = w.spacing;
    l.mesh = w.mesh;
    l.elastic = w.elastic;
    for (std::unique_ptr<Condition>& c : w.conditions) {
      c->restrict_points(db.links.points);
      l.conditions.push_back(std::move(c));
    }
    w.conditions.clear();
    local.bodies.push_back(std::move(l));
    d.bodies_.push_back(std::move(db));
  }
  return out;
}

void Distribution::exchange_state(Scene& local) {
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    DistributedBody& db = bodies_[b];
    if (db.replicated) continue;
    Body& body = local.bodies[b].body;
    pack_state(db.links, body, db.buffers);
    ranks::exchange(db.buffers.send, db.buffers.receive);
    unpack_state(db.links, db.buffers, body);
  }
}

void Distribution::sum_forces(Scene& local, bool with_energy) {
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    DistributedBody& db = bodies_[b];
    if (db.replicated) continue;
    Body& body = local.bodies[b].body;
    pack_ghost_forces(db.links, body, with_energy, db.buffers);
    ranks::exchange(db.buffers.send, db.buffers.receive);
    add_owner_forces(db.links, rank_, db.buffers, with_energy, body);
  }
}

void Distribution::sum_and_max(std::vector<double>& values, std::size_t summed) {
  ranks::all_gather(values, scratch_);
  const std::size_t m = values.size();
  for (std::size_t k = 0; k < m; ++k) {
    double v = scratch_[k];
    for (std::size_t r = 1; r * m < scratch_.size(); ++r)
      v = k < summed ? v + scratch_[r * m + k] : std::max(v, scratch_[r * m + k]);
    values[k] = v;
  }
}

Distribution::Choice Distribution::choose(const Scene& local, double key, std::size_t body,
                                          std::size_t local_point) {
  std::vector<double>& mine = proposal_;  // kept: a step allocates nothing
  mine.assign(6, 0.0);
  mine[0] = key;
  if (key >= 0) {
    const Vec3 x = local.bodies[body].body.reference_position[local_point];
    mine[1] = static_cast<double>(body);
    mine[2] = static_cast<double>(bodies_[body].links.points[local_point]);
    mine[3] = x.x();
    mine[4] = x.y();
    mine[5] = x.z();
  }
  ranks::all_gather(mine, scratch_);
  Choice best;
  for (std::size_t r = 0; r * 6 < scratch_.size(); ++r) {
    const double* c = &scratch_[r * 6];
    if (c[0] < 0) continue;
    const auto cb = static_cast<std::size_t>(c[1]), cp = static_cast<std::size_t>(c[2]);
    const bool better =
        c[0] > best.key ||
        (c[0] == best.key && (cb < best.body || (cb == best.body && cp < best.point)));
    if (!better) continue;
    best.key = c[0];
    best.body = cb;
    best.point = cp;
    best.reference = Vec3(c[3], c[4], c[5]);
  }
  return best;
}

void Distribution::gather(const Scene& local, Scene& whole) {
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const DistributedBody& db = bodies_[b];
    const Body& part = local.bodies[b].body;
    if (db.replicated) {
      // Every rank moved it alike: rank 0's copy is the body.
      if (rank_ == 0) copy_rigid_body(local.bodies[b], whole.bodies[b]);
      continue;
    }
    bytes_.clear();
    for (std::size_t l = 0; l < part.size(); ++l) {
      if (!db.links.owned[l]) continue;
      const double values[kGatheredValues] = {part.displacement[l].x(),
                                              part.displacement[l].y(),
                                              part.displacement[l].z(),
                                              part.velocity[l].x(),
                                              part.velocity[l].y(),
                                              part.velocity[l].z(),
                                              part.acceleration[l].x(),
                                              part.acceleration[l].y(),
                                              part.acceleration[l].z(),
                                              part.force_density[l].x(),
                                              part.force_density[l].y(),
                                              part.force_density[l].z(),
                                              part.external_force_density[l].x(),
                                              part.external_force_density[l].y(),
                                              part.external_force_density[l].z(),
                                              part.strain_energy_density[l]};
      put(bytes_, values, kGatheredValues);
      // An owned point's family is whole in the restriction, in the whole body's order.
      const std::size_t begin = part.family.offset[l], end = part.family.offset[l + 1];
      bytes_.insert(bytes_.end(), part.bond_intact.begin() + static_cast<std::ptrdiff_t>(begin),
                    part.bond_intact.begin() + static_cast<std::ptrdiff_t>(end));
    }
    ranks::gather_to_root(bytes_, gathered_bytes_);
    if (rank_ != 0) continue;
    Body& w = whole.bodies[b].body;
    std::size_t at = 0;
    for (int r = 0; r < ranks_; ++r)
      for (std::size_t g = 0; g < w.size(); ++g) {
        if (db.owner[g] != r) continue;
        double v[kGatheredValues];
        std::memcpy(v, gathered_bytes_.data() + at, sizeof v);
        at += sizeof v;
        w.displacement[g] = Vec3(v[0], v[1], v[2]);
        w.velocity[g] = Vec3(v[3], v[4], v[5]);
        w.acceleration[g] = Vec3(v[6], v[7], v[8]);
        w.force_density[g] = Vec3(v[9], v[10], v[11]);
        w.external_force_density[g] = Vec3(v[12], v[13], v[14]);
        w.strain_energy_density[g] = v[15];
        const std::size_t begin = w.family.offset[g], end = w.family.offset[g + 1];
        std::copy(gathered_bytes_.begin() + static_cast<std::ptrdiff_t>(at),
                  gathered_bytes_.begin() + static_cast<std::ptrdiff_t>(at + end - begin),
                  w.bond_intact.begin() + static_cast<std::ptrdiff_t>(begin));
        at += end - begin;
      }
    if (at != gathered_bytes_.size())
      throw std::logic_error("distributed gather: the ranks' parts do not make up body '" + w.name +
                             "'");
  }
}

void Distribution::scatter(const Scene& whole, Scene& local) const {
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const std::vector<std::uint32_t>& global = bodies_[b].links.points;
    const Body& w = whole.bodies[b].body;
    Body& part = local.bodies[b].body;
    if (bodies_[b].replicated) {
      copy_rigid_body(whole.bodies[b], local.bodies[b]);
      continue;
    }
    if (w.size() != bodies_[b].whole_points || part.size() != global.size())
      throw std::logic_error("distributed scatter: body '" + w.name +
                             "' is not the one this rank's part was cut from");
    for (std::size_t l = 0; l < part.size(); ++l) {
      const std::size_t g = global[l];
      part.displacement[l] = w.displacement[g];
      part.velocity[l] = w.velocity[g];
      part.acceleration[l] = w.acceleration[g];
      part.force_density[l] = w.force_density[g];
      part.external_force_density[l] = w.external_force_density[g];
      part.strain_energy_density[l] = w.strain_energy_density[g];
      // The part's family of l is the whole family of g cut to the kept points, in the same
      // order (an owned point's is whole): walk both.
      std::size_t k = w.family.offset[g];
      const std::size_t k_end = w.family.offset[g + 1];
      for (std::size_t j = part.family.offset[l]; j < part.family.offset[l + 1]; ++j) {
        const std::uint32_t member = global[part.family.neighbour[j]];
        while (k < k_end && w.family.neighbour[k] != member) ++k;
        if (k == k_end)
          throw std::logic_error("distributed scatter: a bond of body '" + w.name +
                                 "' is not in the whole body's family");
        part.bond_intact[j] = w.bond_intact[k++];
      }
    }
  }
}

}  // namespace ckpd
