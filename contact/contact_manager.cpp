#include "contact/contact_manager.hpp"

#include <algorithm>
#include <chrono>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>

#include "base/parallel_policy.hpp"
#include "contact/dem_contact.hpp"
#include "contact/point_cluster.hpp"

namespace ckpd {

struct ContactManager::Pair {
  std::uint32_t body[2] = {0, 0};  // equal for self-contact
  PairLaw law;
  bool self = false;
  std::vector<std::uint32_t> members[2];  // points that can touch the other side (self: [0] only)
  PointGrid grid[2];
};

struct ContactManager::Target {
  std::uint32_t body = 0, point = 0;
  std::uint32_t ref_begin = 0, ref_end = 0;  // into target_refs_
};

namespace {

// Below parallel_thresholds().contact_work (points or targets) a parallel region costs more than
// it saves, and on a shared machine a descheduled thread stalls every barrier; the drift check
// and the boxes stream through memory and are parallel only above contact_scan points.

Box3 bounding_box(const PointSet& body) {
  Box3 box{Vec3::Constant(std::numeric_limits<double>::infinity()),
           Vec3::Constant(-std::numeric_limits<double>::infinity())};
  for (std::size_t i = 0; i < body.size(); ++i) {
    const Vec3 x = body.position(i);
    box.lo = box.lo.cwiseMin(x);
    box.hi = box.hi.cwiseMax(x);
  }
  return box;
}

Box3 grown(const Box3& box, double by) {
  return {box.lo - Vec3::Constant(by), box.hi + Vec3::Constant(by)};
}

bool inside(const Box3& box, const Vec3& x) {
  return (x.array() >= box.lo.array()).all() && (x.array() <= box.hi.array()).all();
}

}  // namespace

ContactManager::ContactManager(std::vector<ContactBody> bodies, ContactSettings settings)
    : bodies_(std::move(bodies)), settings_(std::move(settings)) {
  const std::size_t n = bodies_.size();
  margin_.assign(n, 0);
  drift_limit_.assign(n, 0);
  std::vector<double> widest_radius(n, 0);
  std::vector<std::uint8_t> member(n, 0);
  std::vector<MeshWallContact::Pair> wall_pairs;
  for (std::size_t a = 0; a < n; ++a) {
    if (bodies_[a].wall) {
      // A wall meets the points of its partners, never another wall's surface.
      for (std::size_t b = 0; b < n; ++b)
        if (b != a && !bodies_[b].wall)
          if (const auto law = settings_.law(bodies_, std::min(a, b), std::max(a, b)))
            wall_pairs.push_back({b, a, law->radius, law->coefficient[b < a ? 0 : 1], law->dem});
      continue;
    }
    if (const auto self = settings_.law(bodies_, a, a)) {
      Pair p;
      p.body[0] = p.body[1] = static_cast<std::uint32_t>(a);
      p.law = *self;
      p.self = true;
      p.members[0].resize(bodies_[a].points.size());
      p.grid[0].reserve(bodies_[a].points.size());
      for (std::size_t i = 0; i < p.members[0].size(); ++i)
        p.members[0][i] = static_cast<std::uint32_t>(i);
      self_pairs_.push_back(std::move(p));
    }
    for (std::size_t b = a + 1; b < n; ++b) {
      if (bodies_[b].wall) continue;
      const auto law = settings_.law(bodies_, a, b);
      if (!law) continue;
      if (pair_law_.empty()) pair_law_.resize(n * n);
      pair_law_[a * n + b] = law;
      member[a] = member[b] = 1;
      for (std::size_t c : {a, b}) {
        margin_[c] = std::max(margin_[c], 0.5 * (law->radius + law->skin));
        widest_radius[c] = std::max(widest_radius[c], law->radius);
      }
    }
  }
  // A pair's boxes were apart by more than margin_a + margin_b >= l_c + drift_a + drift_b at the
  // build, so no two of their points come within l_c while each moves less than its drift limit.
  for (std::size_t b = 0; b < n; ++b) {
    drift_limit_[b] = margin_[b] - 0.5 * widest_radius[b];
    // A view without points (a distributed rank's empty share of a body) has no box to pair.
    if (member[b] && bodies_[b].points.size() > 0) {
      members_.push_back(b);
      member_points_ += bodies_[b].points.size();
    }
  }
  // DEM laws anywhere (point pairs or walls): their bookkeeping and springs.
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = a; b < n; ++b)
      if (const auto law = settings_.law(bodies_, a, b); law && law->dem) {
        dem_ = true;
        friction_ = friction_ || law->dem->friction > 0;
      }
  if (friction_) {
    std::vector<std::size_t> points(n);
    for (std::size_t b = 0; b < n; ++b) points[b] = bodies_[b].points.size();
    history_.resize(points);
  }
  built_displacement_.resize(n);
  if (members_.size() >= 2) broad_ = std::make_unique<BroadPhase>(members_);
  if (!wall_pairs.empty())
    walls_ = std::make_unique<MeshWallContact>(bodies_, std::move(wall_pairs));
}

ContactManager::~ContactManager() = default;

ContactManager::HistoryState ContactManager::history() const {
  HistoryState s{evaluation_, damping_dissipated_, friction_dissipated_, {}};
  if (friction_) s.rows = history_.rows(evaluation_);
  if (walls_) {
    const std::vector<ContactHistoryRow> w = walls_->history(evaluation_);
    s.rows.insert(s.rows.end(), w.begin(), w.end());
  }
  return s;
}

void ContactManager::restore_history(const HistoryState& s) {
  evaluation_ = s.evaluation;
  damping_dissipated_ = s.damping_dissipated;
  friction_dissipated_ = s.friction_dissipated;
  std::vector<ContactHistoryRow> pairs, walls;
  for (const ContactHistoryRow& r : s.rows)
    (r.partner_point == kWallPartner ? walls : pairs).push_back(r);
  if (friction_) history_.restore(evaluation_, pairs);
  if (walls_) walls_->restore_history(evaluation_, walls);
  if ((!pairs.empty() && !friction_) || (!walls.empty() && !walls_))
    throw std::invalid_argument("contact history for pairs that have none in this case");
}

void ContactManager::carry_statistics(const ContactStatistics& earlier) {
  stats_.rebuilds += earlier.rebuilds;
  stats_.pairs_checked += earlier.pairs_checked;
  stats_.points_binned += earlier.points_binned;
  stats_.point_pair_tests += earlier.point_pair_tests;
  stats_.candidate_pairs_peak = std::max(stats_.candidate_pairs_peak, earlier.candidate_pairs_peak);
  stats_.points_in_contact_peak =
      std::max(stats_.points_in_contact_peak, earlier.points_in_contact_peak);
  stats_.touching_pairs_peak = std::max(stats_.touching_pairs_peak, earlier.touching_pairs_peak);
  stats_.seconds += earlier.seconds;
}

void ContactManager::rebind(const std::vector<PointSet>& points) {
  if (points.size() != bodies_.size())
    throw std::invalid_argument("contact: rebind with a different number of bodies");
  for (std::size_t b = 0; b < points.size(); ++b) {
    if (points[b].size() != bodies_[b].points.size())
      throw std::invalid_argument("contact: rebind of body '" + std::string(points[b].name) +
                                  "' with a different number of points");
    bodies_[b].points = points[b];
  }
}

bool ContactManager::drifted_beyond_skin() const {
  bool drifted = false;
  const bool parallel = member_points_ > parallel_thresholds().contact_scan;
#pragma omp parallel for schedule(dynamic) reduction(|| : drifted) if (parallel)
  for (std::size_t m = 0; m < members_.size(); ++m) {
    const std::size_t b = members_[m];
    const PointSet& body = bodies_[b].points;
    const std::vector<Vec3>& built = built_displacement_[b];
    const double limit2 = drift_limit_[b] * drift_limit_[b];
    for (std::size_t i = 0; i < body.size(); ++i)
      if ((body.displacement[i] - built[i]).squaredNorm() > limit2) {
        drifted = true;
        break;
      }
  }
  return drifted;
}

void ContactManager::rebuild() {
  std::vector<Box3>& tight = tight_;
  std::vector<Box3>& inflated = inflated_;
  tight.resize(bodies_.size());
  inflated.resize(bodies_.size());
#pragma omp parallel for schedule(dynamic) if (member_points_ > parallel_thresholds().contact_scan)
  for (std::size_t m = 0; m < members_.size(); ++m) {
    const std::size_t b = members_[m];
    tight[b] = bounding_box(bodies_[b].points);
    inflated[b] = grown(tight[b], margin_[b]);
    built_displacement_[b].assign(bodies_[b].points.displacement.begin(),
                                  bodies_[b].points.displacement.end());
  }
  // The laws were found at setup (ContactSettings::law builds names and DEM laws afresh); the
  // pairs reuse the buffers of the last rebuild's.
  broad_->overlapping_pairs(inflated, broad_pairs_);
  const std::size_t n = bodies_.size();
  std::size_t count = 0;
  for (const auto& [a, b] : broad_pairs_) {
    const std::optional<PairLaw>& law = pair_law_[a * n + b];
    if (!law) continue;
    if (count == pairs_.size()) pairs_.emplace_back();
    Pair& p = pairs_[count++];
    // A side holds at most its body's points: room for them all, once per body pair that this
    // slot of the pool has held, so that a growing contact zone allocates nothing in a step.
    for (int s = 0; s < 2; ++s) {
      const std::size_t size = bodies_[s == 0 ? a : b].points.size();
      if (p.members[s].capacity() < size) {
        p.members[s].reserve(size);
        p.grid[s].reserve(size);
      }
    }
    p.body[0] = a;
    p.body[1] = b;
    p.law = *law;
    p.members[0].clear();
    p.members[1].clear();
  }
#pragma omp parallel for schedule(dynamic)
  for (std::size_t k = 0; k < count; ++k) {
    Pair& p = pairs_[k];
    const double reach = p.law.radius + drift_limit_[p.body[0]] + drift_limit_[p.body[1]];
    for (int s = 0; s < 2; ++s) {
      const PointSet& body = bodies_[p.body[s]].points;
      const Box3 zone = grown(tight[p.body[1 - s]], reach);
      for (std::size_t i = 0; i < body.size(); ++i)
        if (inside(zone, body.position(i))) p.members[s].push_back(static_cast<std::uint32_t>(i));
    }
  }
  // Overlapping boxes whose points are nowhere near each other cost nothing further: the pairs
  // kept move to the front, in order (swapped, so that every buffer stays for the next rebuild).
  std::size_t kept = 0;
  for (std::size_t k = 0; k < count; ++k) {
    if (pairs_[k].members[0].empty() || pairs_[k].members[1].empty()) continue;
    if (k != kept) std::swap(pairs_[kept], pairs_[k]);
    ++kept;
  }
  pair_count_ = kept;
  ++stats_.rebuilds;
  index_targets();
}

void ContactManager::index_targets() {
  all_pairs_.clear();
  for (Pair& p : self_pairs_) all_pairs_.push_back(&p);
  for (std::size_t k = 0; k < pair_count_; ++k) all_pairs_.push_back(&pairs_[k]);
  // (body, point, ref) for every point on every side of every pair, grouped by point.
  auto& entries = target_entries_;
  entries.clear();
  // Room for every point of every side of these pairs, the most the lists can hold until the
  // pairs change: a growing contact zone allocates nothing in a step.
  std::size_t most = 0;
  for (const Pair* p : all_pairs_)
    most += bodies_[p->body[0]].points.size() + (p->self ? 0 : bodies_[p->body[1]].points.size());
  if (entries.capacity() < most) {
    entries.reserve(most);
    targets_.reserve(most);
    target_refs_.reserve(most);
    target_energy_.reserve(most);
    if (dem_) target_dem_.reserve(most);
    target_contacts_.reserve(most);
    target_tests_.reserve(most);
  }
  for (std::size_t k = 0; k < all_pairs_.size(); ++k) {
    const Pair& p = *all_pairs_[k];
    for (int s = 0; s < (p.self ? 1 : 2); ++s) {
      const PointSet& side = bodies_[p.body[s]].points;
      for (std::uint32_t i : p.members[s])
        if (side.computes(i))  // another's point is a partner only, never a target
          entries.emplace_back(p.body[s], i, static_cast<std::uint32_t>(2 * k + s));
    }
  }
  std::sort(entries.begin(), entries.end());
  targets_.clear();
  target_refs_.clear();
  for (std::size_t e = 0; e < entries.size(); ++e) {
    const auto [body, point, ref] = entries[e];
    if (targets_.empty() || targets_.back().body != body || targets_.back().point != point) {
      const auto at = static_cast<std::uint32_t>(target_refs_.size());
      targets_.push_back({body, point, at, at});
    }
    target_refs_.push_back(ref);
    ++targets_.back().ref_end;
  }
  target_energy_.assign(targets_.size(), 0);
  if (dem_) target_dem_.assign(targets_.size(), {});
  target_contacts_.assign(targets_.size(), 0);
  target_tests_.assign(targets_.size(), 0);
  built_ = true;
}

void ContactManager::add_forces(double dt) {
  const auto start = std::chrono::steady_clock::now();
  ++evaluation_;
  if (!built_ || (broad_ && drifted_beyond_skin())) {
    if (broad_)
      rebuild();
    else
      index_targets();
  }
  // Bin both sides of every pair (one side for self-contact) at the current positions.
  const std::size_t sides = 2 * all_pairs_.size();
#pragma omp parallel for schedule(dynamic) if (targets_.size() > parallel_thresholds().contact_work)
  for (std::size_t t = 0; t < sides; ++t) {
    Pair& p = *all_pairs_[t / 2];
    const int s = static_cast<int>(t % 2);
    if (p.self && s == 1) continue;
    p.grid[s].build(bodies_[p.body[s]].points, p.members[s], p.law.radius);
  }
  for (const Pair* p : all_pairs_)
    stats_.points_binned += p->members[0].size() + (p->self ? 0 : p->members[1].size());

  pair_touching_.assign(all_pairs_.size(), 0);
  // Each point sums its partners in (body, point) order, whatever the cell lists look like, so a
  // point's force does not depend on which points the last rebuild kept (a run restarted from
  // a checkpoint rebuilds at once and must continue bit for bit).
#pragma omp parallel if (targets_.size() > parallel_thresholds().contact_work / 4)
  {
    struct Contribution {
      std::uint32_t body, point;
      Vec3 force;
      double energy;
      // DEM laws only (zero for the seed law): half of each, as the energy.
      double damping_power = 0, slip_work = 0;
      Vec3 couple = Vec3::Zero();  // (contact point - x^i) x F: a spinning body's or the cluster's
      Vec3 spring = Vec3::Zero();  // the pair's tangential history, in this end's sense
      bool writes_history = false;
      bool operator<(const Contribution& o) const {
        return body != o.body ? body < o.body : point < o.point;
      }
    };
    // Each thread's list outlives the call (OpenMP keeps its threads): no allocation in a step
    // once it has held a point's most contacts.
    static thread_local std::vector<Contribution> found;
    if (found.capacity() < 256) found.reserve(256);
#pragma omp for schedule(dynamic, 64)
    for (std::size_t t = 0; t < targets_.size(); ++t) {
      const Target& target = targets_[t];
      const PointSet& body = bodies_[target.body].points;
      const std::uint32_t i = target.point;
      const Vec3 xi = body.position(i);
      const double vi = body.volume[i];
      std::uint32_t tests = 0;
      bool spin_known = false;  // the spin of i's cluster, found at its first frictional contact
      Vec3 spin = Vec3::Zero();
      found.clear();
      for (std::uint32_t r = target.ref_begin; r < target.ref_end; ++r) {
        const std::uint32_t pair = target_refs_[r] / 2;
        const Pair& p = *all_pairs_[pair];
        const int side = static_cast<int>(target_refs_[r] % 2);
        const int other = p.self ? 0 : 1 - side;
        const double lc = p.law.radius, c = p.law.coefficient[side];
        if (p.law.dem) {
          // A DEM law (dem_law.hpp): both ends of a pair compute the same contact from the same
          // history, each with its own sign (tangential_spring.hpp), and the end that comes
          // first in (body, point) order writes the new history.
          const DemLaw& law = *p.law.dem;
          const std::uint32_t partner_body = p.body[other];
          const PointSet& partner = bodies_[partner_body].points;
          const LawPoint here{vi, body.mass(i)};
          // With friction a deformable end's cluster takes up the couple of the tangential force
          // and lends the contact its spin (point_cluster.hpp), as a rigid body's spin does.
          const bool friction = law.friction > 0;
          const bool here_cluster = friction && has_clusters(body);
          const bool partner_cluster = friction && has_clusters(partner);
          p.grid[other].for_each_near(xi, [&](std::uint32_t j, const Vec3& xj, double vj) {
            ++tests;
            const Vec3 d = xi - xj;
            const double r2 = d.squaredNorm();
            if (r2 >= lc * lc || r2 == 0) return;
            if (p.self && body.bonded(i, j)) return;
            const double distance = std::sqrt(r2);
            const Vec3 n = d / distance;
            // The contact point: the midpoint, or where the two sides' surfaces meet when a DEM
            // sphere takes part (contact_law.hpp); both ends form the same point.
            Vec3 at = 0.5 * (xi + xj);
            const double shift = p.law.side_radius[other] - p.law.side_radius[side];
            if (shift != 0) at += (0.5 * shift) * n;
            // Each end's material velocity at p formed alone, so that the two ends' differences
            // are exactly opposite.
            Vec3 mine = body.velocity_at(i, at), theirs = partner.velocity_at(j, at);
            if (here_cluster) {
              if (!spin_known) {
                spin = cluster_spin(body, i);
                spin_known = true;
              }
              mine += spin.cross(at - xi);
            }
            if (partner_cluster) theirs += cluster_spin(partner, j).cross(at - xj);
            const Vec3 velocity = mine - theirs;
            const bool first = target.body != partner_body ? target.body < partner_body : i < j;
            Vec3 previous = Vec3::Zero();
            if (law.friction > 0)
              previous =
                  first ? history_.find(evaluation_ - 1, target.body, i, partner_body, j)
                        : Vec3(-history_.find(evaluation_ - 1, partner_body, j, target.body, i));
            const DemContact c = dem_contact(law, lc - distance, n, velocity, here,
                                             {vj, partner.mass(j)}, false, previous, dt);
            Contribution f{partner_body, j, c.force, 0.5 * c.energy};
            f.damping_power = 0.5 * c.damping_power;
            f.slip_work = 0.5 * c.slip_work;
            if (body.spins || here_cluster) f.couple = (at - xi).cross(c.force);
            f.spring = c.spring;
            f.writes_history = first && law.friction > 0;
            found.push_back(f);
#pragma omp atomic write
            pair_touching_[pair] = 1;
          });
          continue;
        }
        // Each point pair is met from both ends; each end books half its energy.
        const double quarter_mean = 0.25 * p.law.mean_coefficient();
        p.grid[other].for_each_near(xi, [&](std::uint32_t j, const Vec3& xj, double vj) {
          ++tests;
          const Vec3 d = xi - xj;
          const double r2 = d.squaredNorm();
          if (r2 >= lc * lc || r2 == 0) return;
          // Distance first: the bond lookup is the dearer test, and most pairs fail the other.
          if (p.self && body.bonded(i, j)) return;
          const double distance = std::sqrt(r2), gap = lc - distance;
          const double volumes = vi * vj;
          found.push_back({p.body[other], j, (c * gap / distance * volumes) * d,
                           quarter_mean * volumes * gap * gap});
#pragma omp atomic write
          pair_touching_[pair] = 1;
        });
      }
      std::sort(found.begin(), found.end());
      Vec3 force = Vec3::Zero();
      double energy = 0;
      for (const Contribution& f : found) {
        force += f.force;
        energy += f.energy;
      }
      body.force_density[i] += force / vi;
      if (dem_) {
        DemTotals& totals = target_dem_[t];
        totals = {};
        std::vector<PairHistory::Entry>* written = nullptr;
        for (const Contribution& f : found) {
          totals.damping += f.damping_power;
          totals.friction += f.slip_work;
          totals.couple += f.couple;
          if (!f.writes_history) continue;
          if (!written) written = &history_.start(evaluation_, target.body, i);
          written->push_back({f.body, f.point, f.spring});
        }
      }
      target_energy_[t] = energy;
      target_contacts_[t] = static_cast<std::uint32_t>(found.size());
      target_tests_[t] = tests;
    }
  }
  // Serial sums: the same total on every thread count.
  energy_ = 0;
  std::uint64_t contacts = 0;
  for (std::size_t t = 0; t < targets_.size(); ++t) {
    stats_.point_pair_tests += target_tests_[t];
    // A point another process books (a rigid body every rank computes) is its to count.
    if (!bodies_[targets_[t].body].points.books(targets_[t].point)) continue;
    energy_ += target_energy_[t];
    contacts += target_contacts_[t];
  }
  if (dem_) {
    double damping = 0;
    for (std::size_t t = 0; t < targets_.size(); ++t) {
      const PointSet& points = bodies_[targets_[t].body].points;
      if (points.books(targets_[t].point)) {  // another process books it (see energy_ above)
        damping += target_dem_[t].damping;
        friction_dissipated_ += target_dem_[t].friction;
      }
      if (points.couple)
        *points.couple += target_dem_[t].couple;
      else if (has_clusters(points) && target_dem_[t].couple != Vec3::Zero())
        // A deformable point's couple goes to its cluster's points (other targets' and not):
        // here, serially, in target order, so no two threads write one point.
        add_cluster_couple(points, targets_[t].point, target_dem_[t].couple);
    }
    damping_dissipated_ += dt * damping;
  }
  stats_.points_in_contact = contacts / 2;
  stats_.contact_ends = contacts;
  std::size_t wall_touching = 0;
  if (walls_) {
    walls_->add_forces(dt, evaluation_);
    energy_ += walls_->energy();
    damping_dissipated_ += walls_->damping_dissipated();
    friction_dissipated_ += walls_->friction_dissipated();
    stats_.points_in_contact += walls_->points_in_contact();
    stats_.contact_ends += 2 * walls_->points_in_contact();
    for (std::size_t k = 0; k < walls_->pairs(); ++k) wall_touching += walls_->pair_touching(k);
  }
  stats_.points_in_contact_peak = std::max(stats_.points_in_contact_peak, stats_.points_in_contact);
  stats_.touching_pairs =
      wall_touching + static_cast<std::size_t>(std::count(pair_touching_.begin(),
                                                          pair_touching_.end(), std::uint8_t{1}));
  stats_.touching_pairs_peak = std::max(stats_.touching_pairs_peak, stats_.touching_pairs);
  stats_.candidate_pairs = all_pairs_.size();
  stats_.candidate_pairs_peak = std::max(stats_.candidate_pairs_peak, stats_.candidate_pairs);
  stats_.pairs_checked += all_pairs_.size();
  stats_.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace ckpd
