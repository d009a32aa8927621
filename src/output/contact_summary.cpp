#include "src/output/contact_summary.hpp"

#include "src/engine/contact_coupling.hpp"

namespace ckpd {

namespace {

nlohmann::ordered_json vector_json(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

nlohmann::ordered_json rigid_bodies(const Simulation& sim) {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const SceneBody& sb : sim.whole_scene().bodies) {
    if (!sb.rigid) continue;
    const RigidMotion& r = *sb.rigid;
    list.push_back({{"name", sb.body.name},
                    {"motion", r.prescribed() ? "prescribed" : "free"},
                    {"mass", r.mass()},
                    {"centre", vector_json(r.centre())},
                    {"velocity", vector_json(r.velocity())},
                    {"angular_velocity", vector_json(r.angular_velocity())}});
  }
  return list;
}

// Every body's centre of mass and mean velocity (momentum / mass): where the bodies went.
nlohmann::ordered_json body_motion(const Simulation& sim) {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const SceneBody& sb : sim.whole_scene().bodies) {
    const Body& b = sb.body;
    Vec3 centre = Vec3::Zero(), momentum = Vec3::Zero();
    double volume = 0, mass = 0;
    for (std::size_t i = 0; i < b.size(); ++i) {
      centre += b.volume[i] * b.current_position(i);
      volume += b.volume[i];
      momentum += b.density * b.volume[i] * b.velocity[i];
      mass += b.density * b.volume[i];
    }
    list.push_back({{"name", b.name},
                    {"centre", vector_json(centre / volume)},
                    {"velocity", vector_json(mass > 0 ? Vec3(momentum / mass) : Vec3::Zero())}});
  }
  return list;
}

}  // namespace

nlohmann::ordered_json contact_summary(const Simulation& sim) {
  nlohmann::ordered_json j;
  const ContactManager* contact = sim.contact();
  j["active"] = contact != nullptr;
  if (contact) {
    const ContactStatistics& s = contact->statistics();
    j["broad_phase"] = contact->has_broad_phase();
    j["broad_phase_rebuilds"] = s.rebuilds;
    j["pairs_checked"] = s.pairs_checked;
    j["candidate_pairs_peak"] = s.candidate_pairs_peak;
    j["touching_pairs_peak"] = s.touching_pairs_peak;
    // Distributed memory: over all ranks, counted at every step.
    j["point_pairs_in_contact_peak"] =
        sim.distribution() ? sim.contact_pairs_peak() : s.points_in_contact_peak;
    j["point_pairs_in_contact"] = sim.distribution() ? sim.contact_pairs() : s.points_in_contact;
    j["points_binned"] = s.points_binned;
    j["point_pair_tests"] = s.point_pair_tests;
    j["contact_seconds"] = s.seconds;
    nlohmann::ordered_json laws = nlohmann::ordered_json::array();
    for (const ContactLawNote& n : contact_law_notes(sim.whole_scene()))
      laws.push_back({{"bodies", n.bodies},
                      {"law", n.law},
                      {"friction", n.friction},
                      {"damping_ratio", n.damping_ratio}});
    j["laws"] = laws;
    if (sim.distribution()) {
      // Distributed memory (src/engine/contact_ghosts.hpp): the statistics above are rank 0's.
      j["statistics_of"] =
          "all ranks for the point pairs in contact, else rank 0 (its owned points and their "
          "contact ghosts)";
      j["contact_ghost_selections"] = sim.contact_ghost_selections();
      j["contact_ghosts_most_on_a_rank"] = sim.contact_ghosts_peak();
      j["contact_ghost_bytes_per_step_most_on_a_rank"] =
          sim.contact_ghosts_peak() * 6 * sizeof(double);
    }
    const Energies e = sim.energies();  // on distributed memory the sums over ranks
    j["damping_dissipated"] = e.contact_damping;
    j["friction_dissipated"] = e.contact_friction;
  }
  j["body_force_seconds"] = sim.body_force_seconds();
  j["rigid_bodies"] = rigid_bodies(sim);
  j["body_motion"] = body_motion(sim);
  return j;
}

}  // namespace ckpd
