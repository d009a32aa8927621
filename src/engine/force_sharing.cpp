#include "src/engine/force_sharing.hpp"

#include "bodies/state_based_model.hpp"
#include "src/engine/ranks.hpp"

namespace ckpd {

Decomposition share_force_work(Scene& scene, int rank, int ranks) {
  std::vector<const Body*> bodies;
  std::vector<bool> rigid;
  for (const SceneBody& sb : scene.bodies) {
    bodies.push_back(&sb.body);
    rigid.push_back(sb.rigid.has_value());
  }
  Decomposition d = decompose(bodies, rigid, ranks);
  if (ranks == 1) return d;
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    Body& body = scene.bodies[b].body;
    body.owned_centres.clear();
    if (!force_work_can_be_shared(scene.bodies[b])) continue;  // evaluated whole on every rank
    body.owned_centres.resize(body.size());
    for (std::size_t i = 0; i < body.size(); ++i)
      body.owned_centres[i] = d.owner[b][i] == rank ? 1 : 0;
  }
  return d;
}

bool force_work_can_be_shared(const SceneBody& sb) {
  return !sb.rigid && sb.body.model != &state_based_kernels() && !sb.far_field;
}

std::size_t shared_force_values(const Scene& scene, bool with_energy) {
  std::size_t m = 0;
  for (const SceneBody& sb : scene.bodies)
    if (shares_force_work(sb.body)) m += shared_force_values(sb.body, with_energy);
  return m;
}

void sum_shared_forces(Scene& scene, bool with_energy, std::vector<std::uint64_t>& inverted,
                       ForceSharingBuffers& buffers) {
  const std::size_t m = shared_force_values(scene, with_energy);
  if (m == 0) return;
  std::vector<double>& v = buffers.values;
  v.resize(m);
  std::size_t at = 0;
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    const Body& body = scene.bodies[b].body;
    if (!shares_force_work(body)) continue;
    for (const Vec3& f : body.force_density) {
      v[at++] = f.x();
      v[at++] = f.y();
      v[at++] = f.z();
    }
    if (!with_energy) continue;
    for (const double e : body.strain_energy_density) v[at++] = e;
    v[at++] = static_cast<double>(inverted[b]);  // an integer below 2^53: summed exactly
  }
  ranks::sum_in_rank_order(v, buffers.gathered);
  at = 0;
  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    Body& body = scene.bodies[b].body;
    if (!shares_force_work(body)) continue;
    for (Vec3& f : body.force_density) {
      f = Vec3(v[at], v[at + 1], v[at + 2]);
      at += 3;
    }
    if (!with_energy) continue;
    for (double& e : body.strain_energy_density) e = v[at++];
    inverted[b] = static_cast<std::uint64_t>(v[at++]);
  }
}

}  // namespace ckpd
