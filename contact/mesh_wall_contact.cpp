#include "contact/mesh_wall_contact.hpp"

#include "contact/mesh_wall.hpp"
#include "contact/wall_law.hpp"

namespace ckpd {

namespace {

constexpr std::size_t kParallelPoints = 2048;

// Force densities on the six carriers whose total force is `force` and whose total torque
// about their centre is `torque`: each takes force/6; the torque about e_k comes from the
// pair along the longer of the other two axes, pushed both ways across it.
void spread_to_carriers(Body& carriers, const MeshWall& wall, const Eigen::Matrix3d& rotation,
                        const Vec3& force, const Vec3& torque) {
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

}  // namespace

MeshWallContact::MeshWallContact(const std::vector<ContactBody>& bodies, std::vector<Pair> pairs)
    : bodies_(bodies), pairs_(std::move(pairs)) {
  pair_touching_.assign(pairs_.size(), 0);
}

void MeshWallContact::add_forces() {
  energy_ = 0;
  touching_ = 0;
  for (std::size_t k = 0; k < pairs_.size(); ++k) {
    const Pair& p = pairs_[k];
    Body& body = *bodies_[p.body].body;
    Body& carriers = *bodies_[p.wall].body;
    const MeshWall& wall = *bodies_[p.wall].wall;
    const MeshWall::Pose pose = wall.pose(carriers);
    const Eigen::Matrix3d back = pose.rotation.transpose();
    const Vec3 c0 = wall.carriers().centre;
    const std::size_t n = body.size();
    force_.assign(n, Vec3::Zero());
    point_energy_.assign(n, 0.0);
#pragma omp parallel for schedule(dynamic, 256) if (n > kParallelPoints)
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 X = back * (body.current_position(i) - pose.centre) + c0;
      const auto hit = wall.nearest(X, p.radius);
      if (!hit) continue;
      force_[i] =
          (p.coefficient * wall_force(hit->height, p.radius)) * (pose.rotation * hit->outward);
      point_energy_[i] = p.coefficient * body.volume[i] * wall_energy(hit->height, p.radius);
    }
    // Serial sums in point order: the same totals on every thread count.
    Vec3 reaction = Vec3::Zero(), torque = Vec3::Zero();
    std::size_t touching = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (point_energy_[i] == 0 && force_[i].isZero()) continue;
      ++touching;
      body.force_density[i] += force_[i];
      const Vec3 f = -body.volume[i] * force_[i];
      reaction += f;
      torque += (body.current_position(i) - pose.centre).cross(f);
      energy_ += point_energy_[i];
    }
    pair_touching_[k] = touching > 0;
    touching_ += touching;
    if (touching) spread_to_carriers(carriers, wall, pose.rotation, reaction, torque);
  }
}

}  // namespace ckpd
