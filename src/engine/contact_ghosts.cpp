#include "src/engine/contact_ghosts.hpp"

#include <algorithm>
#include <limits>
#include <utility>

#include "src/engine/contact_coupling.hpp"
#include "src/engine/distribution.hpp"
#include "src/engine/ranks.hpp"

namespace ckpd {

namespace {

// A ghost's selection message: body, whole-body index, reference position, volume,
// displacement, velocity. A step's message: displacement and velocity.
constexpr std::size_t kSelectionValues = 12;
constexpr std::size_t kStepValues = 6;

}  // namespace

struct ContactGhosts::View {
  const Body* part = nullptr;
  std::vector<std::uint32_t> global;  // view point -> whole-body index, increasing
  std::vector<std::int64_t> local;    // view point -> restriction index; -1: not held here
  std::vector<Vec3> reference, displacement, velocity, force;
  std::vector<double> volume;
  std::vector<std::uint8_t> owned;   // PointSet::computed
  std::vector<std::uint8_t> booked;  // PointSet::booked
  std::vector<Vec3> built;           // per restriction point: its displacement at the selection
};

ContactGhosts::ContactGhosts(Scene& local, const Distribution& distribution)
    : local_(local), distribution_(distribution) {
  const std::vector<ContactBody> bodies = contact_bodies(std::as_const(local_));
  double widest = 0, skin = 0;
  for (std::size_t a = 0; a < bodies.size(); ++a)
    for (std::size_t b = a; b < bodies.size(); ++b)
      if (const std::optional<PairLaw> law = local_.contact.law(bodies, a, b)) {
        widest = std::max(widest, law->radius);
        skin = std::max(skin, law->skin > 0 ? law->skin : law->radius);
      }
  reach_ = widest + skin;
  drift_limit_ = 0.5 * skin;
  views_.resize(local_.bodies.size());
  points_.resize(views_.size());
  send_.resize(static_cast<std::size_t>(distribution_.ranks()));
  receive_.resize(send_.size());
  send_buffer_.resize(send_.size());
  receive_buffer_.resize(send_.size());
}

ContactGhosts::~ContactGhosts() = default;

std::size_t ContactGhosts::ghosts() const {
  std::size_t n = 0;
  for (const auto& r : receive_) n += r.size();
  return n;
}

bool ContactGhosts::drifted() const {
  const double limit2 = drift_limit_ * drift_limit_;
  for (std::size_t b = 0; b < views_.size(); ++b) {
    if (local_.bodies[b].wall) continue;  // no ghosts depend on a wall's motion
    const Body& part = local_.bodies[b].body;
    const std::vector<std::uint8_t>& owned = distribution_.body(b).links.owned;
    for (std::size_t l = 0; l < part.size(); ++l)
      if (owned[l] && (part.displacement[l] - views_[b].built[l]).squaredNorm() > limit2)
        return true;
  }
  return false;
}

void ContactGhosts::select() {
  const std::size_t ranks = send_.size();
  const auto me = static_cast<std::size_t>(distribution_.rank());
  // This rank's box of its owned deformable points, every body together; each rigid body's box
  // (every rank holds and computes the rigid bodies whole, so each needs their partners).
  constexpr double inf = std::numeric_limits<double>::infinity();
  Vec3 lo = Vec3::Constant(inf), hi = Vec3::Constant(-inf);
  std::vector<std::pair<Vec3, Vec3>> rigid_boxes;
  for (std::size_t b = 0; b < views_.size(); ++b) {
    const Body& part = local_.bodies[b].body;
    const bool rigid = distribution_.body(b).replicated;
    // A mesh wall meets each point alone (its surface is every rank's): no ghosts for it.
    if (rigid && local_.bodies[b].wall) continue;
    if (rigid) rigid_boxes.emplace_back(Vec3::Constant(inf), Vec3::Constant(-inf));
    Vec3& box_lo = rigid ? rigid_boxes.back().first : lo;
    Vec3& box_hi = rigid ? rigid_boxes.back().second : hi;
    const std::vector<std::uint8_t>& owned = distribution_.body(b).links.owned;
    for (std::size_t l = 0; l < part.size(); ++l) {
      if (!owned[l]) continue;
      const Vec3 x = part.reference_position[l] + part.displacement[l];
      box_lo = box_lo.cwiseMin(x);
      box_hi = box_hi.cwiseMax(x);
    }
  }
  const std::vector<double> box{lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z()};
  std::vector<double> boxes;
  ranks::all_gather(box, boxes);
  const auto inside = [this](const Vec3& x, const Vec3& box_lo, const Vec3& box_hi) {
    return (x.array() >= box_lo.array() - reach_).all() &&
           (x.array() <= box_hi.array() + reach_).all();
  };
  // To every other rank the owned points inside its box grown by the reach.
  std::vector<double> counts(ranks, 0.0);
  for (std::size_t q = 0; q < ranks; ++q) {
    send_[q].clear();
    send_buffer_[q].clear();
    if (q == me) continue;
    const Vec3 qlo(boxes[6 * q], boxes[6 * q + 1], boxes[6 * q + 2]);
    const Vec3 qhi(boxes[6 * q + 3], boxes[6 * q + 4], boxes[6 * q + 5]);
    for (std::size_t b = 0; b < views_.size(); ++b) {
      const Body& part = local_.bodies[b].body;
      const DistributedBody& db = distribution_.body(b);
      if (db.replicated) continue;  // q holds it
      for (std::size_t l = 0; l < part.size(); ++l) {
        if (!db.links.owned[l]) continue;
        const Vec3 x = part.reference_position[l] + part.displacement[l];
        bool near_rigid = false;
        for (const auto& [rlo, rhi] : rigid_boxes) near_rigid = near_rigid || inside(x, rlo, rhi);
        if (!near_rigid && !inside(x, qlo, qhi)) continue;
        send_[q].emplace_back(static_cast<std::uint32_t>(b), static_cast<std::uint32_t>(l));
        const Vec3& X = part.reference_position[l];
        const Vec3& u = part.displacement[l];
        const Vec3& v = part.velocity[l];
        send_buffer_[q].insert(
            send_buffer_[q].end(),
            {static_cast<double>(b), static_cast<double>(db.links.points[l]), X.x(), X.y(), X.z(),
             part.volume[l], u.x(), u.y(), u.z(), v.x(), v.y(), v.z()});
      }
    }
    counts[q] = static_cast<double>(send_[q].size());
  }
  std::vector<double> all_counts;
  ranks::all_gather(counts, all_counts);
  for (std::size_t q = 0; q < ranks; ++q)
    receive_buffer_[q].assign(
        q == me ? 0 : kSelectionValues * static_cast<std::size_t>(all_counts[q * ranks + me]), 0.0);
  ranks::exchange(send_buffer_, receive_buffer_);
  build_views();
}

void ContactGhosts::build_views() {
  const std::size_t ranks = send_.size();
  // Each body's view: owned points and ghosts in increasing whole-body index.
  struct Entry {
    std::uint32_t global;
    std::uint32_t from;  // the rank it came from; `ranks`: owned here
    std::uint32_t at;    // owned: its local index; a ghost: its place in the message
    bool operator<(const Entry& o) const { return global < o.global; }
  };
  std::vector<std::vector<Entry>> entries(views_.size());
  for (std::size_t b = 0; b < views_.size(); ++b) {
    const DistributedBody& db = distribution_.body(b);
    for (std::size_t l = 0; l < db.links.points.size(); ++l)
      if (db.links.owned[l])
        entries[b].push_back(
            {db.links.points[l], static_cast<std::uint32_t>(ranks), static_cast<std::uint32_t>(l)});
  }
  for (std::size_t q = 0; q < ranks; ++q) {
    const std::vector<double>& m = receive_buffer_[q];
    receive_[q].assign(m.size() / kSelectionValues, {0, 0});
    for (std::size_t k = 0; k * kSelectionValues < m.size(); ++k) {
      const auto b = static_cast<std::size_t>(m[k * kSelectionValues]);
      entries[b].push_back({static_cast<std::uint32_t>(m[k * kSelectionValues + 1]),
                            static_cast<std::uint32_t>(q), static_cast<std::uint32_t>(k)});
    }
  }
  std::vector<ContactBody> bodies;
  for (std::size_t b = 0; b < views_.size(); ++b) {
    std::sort(entries[b].begin(), entries[b].end());
    View& view = views_[b];
    SceneBody& sb = local_.bodies[b];
    const Body& part = sb.body;
    const std::vector<std::uint32_t>& held = distribution_.body(b).links.points;
    const std::size_t n = entries[b].size();
    view.part = &part;
    view.global.resize(n);
    view.local.resize(n);
    view.reference.resize(n);
    view.displacement.resize(n);
    view.velocity.resize(n);
    view.force.assign(n, Vec3::Zero());
    view.volume.resize(n);
    view.owned.resize(n);
    view.booked.resize(n);
    const bool books_all = !distribution_.body(b).replicated || distribution_.rank() == 0;
    for (std::size_t v = 0; v < n; ++v) {
      const Entry& e = entries[b][v];
      view.global[v] = e.global;
      const auto it = std::lower_bound(held.begin(), held.end(), e.global);
      view.local[v] = it != held.end() && *it == e.global ? it - held.begin() : -1;
      view.owned[v] = e.from == ranks ? 1 : 0;
      view.booked[v] = view.owned[v] && books_all ? 1 : 0;
      if (view.owned[v]) {
        view.reference[v] = part.reference_position[e.at];
        view.displacement[v] = part.displacement[e.at];
        view.velocity[v] = part.velocity[e.at];
        view.volume[v] = part.volume[e.at];
        continue;
      }
      const double* m = &receive_buffer_[e.from][e.at * kSelectionValues];
      view.reference[v] = Vec3(m[2], m[3], m[4]);
      view.volume[v] = m[5];
      view.displacement[v] = Vec3(m[6], m[7], m[8]);
      view.velocity[v] = Vec3(m[9], m[10], m[11]);
      receive_[e.from][e.at] = {static_cast<std::uint32_t>(b), static_cast<std::uint32_t>(v)};
    }
    view.built = part.displacement;
    // The view has the body's contact role and constants; its points are the view's.
    PointSet p = point_set(sb);  // a free rigid body's couple included
    p.reference = view.reference;
    p.displacement = view.displacement;
    p.velocity = view.velocity;
    p.volume = view.volume;
    p.force_density = view.force;
    p.computed = view.owned;
    p.booked = view.booked;
    // Self-contact's bond test: only an owned point asks (ghosts are never targets), and its
    // whole family is in the restriction; a partner outside the restriction is no member of it.
    p.bonds = {&view, [](const void* context, std::uint32_t i, std::uint32_t j) {
                 const View& w = *static_cast<const View*>(context);
                 const std::int64_t li = w.local[i], lj = w.local[j];
                 return li >= 0 && lj >= 0 &&
                        joined_by_intact_bond(*w.part, static_cast<std::uint32_t>(li),
                                              static_cast<std::uint32_t>(lj));
               }};
    // The cluster of a frictional contact needs families the view does not hold (DEM laws are
    // not taken here).
    p.family_offset = {};
    p.family_neighbour = {};
    p.bond_intact = {};
    points_[b] = p;
    bodies.push_back(contact_body(sb, p));
  }
  // A new manager for the new views, continuing the old one's evaluation count and statistics.
  std::unique_ptr<ContactManager> manager =
      std::make_unique<ContactManager>(std::move(bodies), local_.contact);
  if (manager_) {
    manager->restore_history(manager_->history());
    manager->carry_statistics(manager_->statistics());
  }
  manager_ = std::move(manager);
  ++selections_;
  valid_ = true;
}

void ContactGhosts::refresh() {
  for (std::size_t q = 0; q < send_.size(); ++q) {
    std::vector<double>& out = send_buffer_[q];
    out.resize(kStepValues * send_[q].size());
    for (std::size_t k = 0; k < send_[q].size(); ++k) {
      const auto [b, l] = send_[q][k];
      const Body& part = local_.bodies[b].body;
      const Vec3& u = part.displacement[l];
      const Vec3& v = part.velocity[l];
      double* m = &out[k * kStepValues];
      m[0] = u.x();
      m[1] = u.y();
      m[2] = u.z();
      m[3] = v.x();
      m[4] = v.y();
      m[5] = v.z();
    }
    receive_buffer_[q].resize(kStepValues * receive_[q].size());
  }
  ranks::exchange(send_buffer_, receive_buffer_);
  for (std::size_t q = 0; q < receive_.size(); ++q)
    for (std::size_t k = 0; k < receive_[q].size(); ++k) {
      const auto [b, v] = receive_[q][k];
      const double* m = &receive_buffer_[q][k * kStepValues];
      views_[b].displacement[v] = Vec3(m[0], m[1], m[2]);
      views_[b].velocity[v] = Vec3(m[3], m[4], m[5]);
    }
  for (View& view : views_)
    for (std::size_t v = 0; v < view.global.size(); ++v)
      if (view.owned[v]) {
        const auto l = static_cast<std::size_t>(view.local[v]);
        view.displacement[v] = view.part->displacement[l];
        view.velocity[v] = view.part->velocity[l];
      }
}

void ContactGhosts::add_forces(double dt) {
  if (ranks::any(!valid_ || drifted()))
    select();
  else
    refresh();
  for (View& view : views_) std::fill(view.force.begin(), view.force.end(), Vec3::Zero());
  // A rigid body's spin is the step's (a DEM contact's velocity at the contact point).
  for (std::size_t b = 0; b < views_.size(); ++b)
    if (const SceneBody& sb = local_.bodies[b]; sb.rigid)
      points_[b].angular_velocity = sb.rigid->angular_velocity();
  manager_->rebind(points_);
  manager_->add_forces(dt);
  sum_wall_reactions();
  for (std::size_t b = 0; b < views_.size(); ++b) {
    const View& view = views_[b];
    Body& part = local_.bodies[b].body;
    for (std::size_t v = 0; v < view.global.size(); ++v)
      if (view.owned[v])
        part.force_density[static_cast<std::size_t>(view.local[v])] += view.force[v];
  }
}

void ContactGhosts::sum_wall_reactions() {
  // Each rank spread the reactions of the points it books to the walls' carriers; the carriers'
  // forces are their sums over ranks, in rank order (the same bits on every rank).
  wall_forces_.clear();
  for (std::size_t b = 0; b < views_.size(); ++b)
    if (local_.bodies[b].wall)
      for (const Vec3& f : views_[b].force)
        wall_forces_.insert(wall_forces_.end(), {f.x(), f.y(), f.z()});
  if (wall_forces_.empty()) return;
  ranks::sum_in_rank_order(wall_forces_, gathered_);
  std::size_t at = 0;
  for (std::size_t b = 0; b < views_.size(); ++b)
    if (local_.bodies[b].wall)
      for (Vec3& f : views_[b].force) {
        f = Vec3(wall_forces_[at], wall_forces_[at + 1], wall_forces_[at + 2]);
        at += 3;
      }
}

void ContactGhosts::restore_history(const ContactManager::HistoryState& state) {
  manager_->restore_history(state);
}

}  // namespace ckpd
