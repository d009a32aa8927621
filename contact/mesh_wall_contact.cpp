#include "contact/mesh_wall_contact.hpp"

#include <limits>
#include <stdexcept>

#include "base/parallel_policy.hpp"
#include "contact/dem_contact.hpp"
#include "contact/mesh_wall.hpp"
#include "contact/wall_law.hpp"

namespace ckpd {

namespace {

// Force densities on the six carriers whose total force is `force` and whose total torque
// about their centre is `torque`: each takes force/6; the torque about e_k comes from the
// pair along the longer of the other two axes, pushed both ways across it.
void spread_to_carriers(const PointSet& carriers, const MeshWall& wall,
                        const Eigen::Matrix3d& rotation, const Vec3& force, const Vec3& torque) {
  const WallCarriers& c = wall.carriers();
  Vec3 f[6];
  for (Vec3& x : f) x = force / 6;
  const Eigen::Matrix3d axes = rotation * c.axes;  // current e_k
  for (int k = 0; k < 3; ++k) {
    const double tau = torque.dot(axes.col(k));
    if (tau == 0) continue;
    const int l = (k + 1) % 3, m = (k + 2) % 3;
    // e_l x e_m = e_k: the pair along e_l pushed along +-e_m, or the pair along e_m along -+e_l.
    if (c.half_length[l] >= c.half_length[m]) {
      const Vec3 g = tau / (2 * c.half_length[l]) * axes.col(m);
      f[2 * l] += g;
      f[2 * l + 1] -= g;
    } else {
      const Vec3 g = -tau / (2 * c.half_length[m]) * axes.col(l);
      f[2 * m] += g;
      f[2 * m + 1] -= g;
    }
  }
  for (int k = 0; k < 6; ++k) carriers.force_density[k] += f[k] / carriers.volume[k];
}

constexpr std::uint64_t kNever = std::numeric_limits<std::uint64_t>::max();

}  // namespace

MeshWallContact::MeshWallContact(const std::vector<ContactBody>& bodies, std::vector<Pair> pairs)
    : bodies_(bodies), pairs_(std::move(pairs)) {
  pair_touching_.assign(pairs_.size(), 0);
  spring_.resize(pairs_.size());
  stamp_.resize(pairs_.size());
  for (std::size_t k = 0; k < pairs_.size(); ++k)
    if (pairs_[k].dem && pairs_[k].dem->friction > 0) {
      spring_[k].assign(bodies_[pairs_[k].body].points.size(), Vec3::Zero());
      stamp_[k].assign(bodies_[pairs_[k].body].points.size(), kNever);
    }
}

std::vector<ContactHistoryRow> MeshWallContact::history(std::uint64_t evaluation) const {
  std::vector<ContactHistoryRow> rows;
  for (std::size_t k = 0; k < pairs_.size(); ++k)
    for (std::uint32_t i = 0; i < stamp_[k].size(); ++i)
      if (stamp_[k][i] == evaluation)
        rows.push_back({static_cast<std::uint32_t>(pairs_[k].body), i,
                        static_cast<std::uint32_t>(pairs_[k].wall), kWallPartner, spring_[k][i]});
  return rows;
}

void MeshWallContact::restore_history(std::uint64_t evaluation,
                                      const std::vector<ContactHistoryRow>& rows) {
  for (auto& stamps : stamp_) std::fill(stamps.begin(), stamps.end(), kNever);
  for (const ContactHistoryRow& r : rows) {
    std::size_t k = 0;
    while (k < pairs_.size() && !(pairs_[k].body == r.body && pairs_[k].wall == r.partner_body))
      ++k;
    if (k == pairs_.size() || r.point >= stamp_[k].size())
      throw std::invalid_argument("contact history for a wall pair this case does not have");
    stamp_[k][r.point] = evaluation;
    spring_[k][r.point] = r.spring;
  }
}

void MeshWallContact::add_forces(double dt, std::uint64_t evaluation) {
  energy_ = 0;
  touching_ = 0;
  damping_ = friction_ = 0;
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    const Pair& p = pairs_[k];
    if (p.dem) {
      add_dem_forces(k, dt, evaluation);
      continue;
    }
    const PointSet& body = bodies_[p.body].points;
    const PointSet& carriers = bodies_[p.wall].points;
    const MeshWall& wall = *bodies_[p.wall].wall;
    const MeshWall::Pose pose = wall.pose(carriers);
    const Eigen::Matrix3d back = pose.rotation.transpose();
    const Vec3 c0 = wall.carriers().centre;
    const std::size_t n = body.size();
    force_.assign(n, Vec3::Zero());
    point_energy_.assign(n, 0.0);
#pragma omp parallel for schedule(dynamic, 256) if (n > parallel_thresholds().contact_work)
    for (std::size_t i = 0; i < n; ++i) {
      if (!body.computes(i)) continue;  // a partner of other points only
      const Vec3 X = back * (body.position(i) - pose.centre) + c0;
      const auto hit = wall.nearest(X, p.radius);
      if (!hit) continue;
      force_[i] =
          (p.coefficient * wall_force(hit->height, p.radius)) * (pose.rotation * hit->outward);
      point_energy_[i] = p.coefficient * body.volume[i] * wall_energy(hit->height, p.radius);
    }
    book(k, pose, 0);
  }
}

void MeshWallContact::book(std::size_t k, const MeshWall::Pose& pose, double dt) {
  const Pair& p = pairs_[k];
  const PointSet& body = bodies_[p.body].points;
  const bool dem = p.dem != nullptr;
  // Serial sums in point order: the same totals on every thread count.
  Vec3 reaction = Vec3::Zero(), torque = Vec3::Zero();
  std::size_t touching = 0;
  for (std::size_t i = 0; i < body.size(); ++i) {
    if (point_energy_[i] == 0 && force_[i].isZero()) continue;
    body.force_density[i] += force_[i];
    if (dem && body.couple) *body.couple += couple_[i];
    // A point another process books (a rigid body every rank computes) leaves the reaction,
    // energy and dissipation to that process: the processes' reactions add up to the whole.
    if (!body.books(i)) continue;
    ++touching;
    const Vec3 f = -body.volume[i] * force_[i];
    reaction += f;
    // The seed law's reaction acts through the point, a DEM law's at the contact point.
    torque += ((dem ? at_[i] : body.position(i)) - pose.centre).cross(f);
    energy_ += point_energy_[i];
    if (!dem) continue;
    damping_ += dt * point_damping_[i];
    friction_ += point_slip_[i];
  }
  pair_touching_[k] = touching > 0;
  touching_ += touching;
  if (touching)
    spread_to_carriers(bodies_[p.wall].points, *bodies_[p.wall].wall, pose.rotation, reaction,
                       torque);
}

void MeshWallContact::add_dem_forces(std::size_t k, double dt, std::uint64_t evaluation) {
  const Pair& p = pairs_[k];
  const DemLaw& law = *p.dem;
  const PointSet& body = bodies_[p.body].points;
  const PointSet& carriers = bodies_[p.wall].points;
  const MeshWall& wall = *bodies_[p.wall].wall;
  const MeshWall::Pose pose = wall.pose(carriers);
  const Eigen::Matrix3d back = pose.rotation.transpose();
  const Vec3 c0 = wall.carriers().centre;
  const std::size_t n = body.size();
  const bool history = law.friction > 0;
  force_.assign(n, Vec3::Zero());
  point_energy_.assign(n, 0.0);
  at_.assign(n, Vec3::Zero());
  couple_.assign(n, Vec3::Zero());
  point_damping_.assign(n, 0.0);
  point_slip_.assign(n, 0.0);
  constexpr double kWallMass = std::numeric_limits<double>::infinity();
#pragma omp parallel for schedule(dynamic, 256) if (n > parallel_thresholds().contact_work)
  for (std::size_t i = 0; i < n; ++i) {
    if (!body.computes(i)) continue;
    const Vec3 x = body.position(i);
    const auto hit = wall.nearest(back * (x - pose.centre) + c0, p.radius);
    if (!hit) continue;
    const Vec3 normal = pose.rotation * hit->outward;
    const Vec3 at = pose.rotation * (hit->point - c0) + pose.centre;
    // The wall's material at p moves as its carriers' rigid motion.
    const Vec3 velocity = body.velocity_at(i, at) - carriers.velocity_at(0, at);
    const Vec3 previous = history && stamp_[k][i] == evaluation - 1 ? spring_[k][i] : Vec3::Zero();
    const DemContact c =
        dem_contact(law, p.radius - hit->height, normal, velocity, {body.volume[i], body.mass(i)},
                    {0, kWallMass}, true, previous, dt);
    force_[i] = c.force / body.volume[i];
    point_energy_[i] = c.energy;
    at_[i] = at;
    if (body.spins) couple_[i] = (at - x).cross(c.force);
    point_damping_[i] = c.damping_power;
    point_slip_[i] = c.slip_work;
    if (history) {
      spring_[k][i] = c.spring;
      stamp_[k][i] = evaluation;
    }
  }
  book(k, pose, dt);
}

}  // namespace ckpd
