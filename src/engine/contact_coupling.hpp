#pragma once
// Ties a scene's bodies to the contact library: the point-set views contact sees them through
// (contact/point_set.hpp), which bodies take part and how, the contact manager a run needs (none
// when no two bodies interact and no body has self-contact), and the stable-step estimate with
// the contact stiffness added (contact_stiffness.hpp).
#include <memory>
#include <vector>

#include "bodies/body.hpp"
#include "contact/contact_manager.hpp"
#include "src/engine/scene.hpp"

namespace ckpd {

// The view of a body contact works on; `force_density` and a rigid body's couple are writable.
PointSet point_set(SceneBody& body);
// The same without the force and the couple: for the questions that only read (laws, stiffness
// bounds).
PointSet point_set(const SceneBody& body);

// The body's contact role (rigid, prescribed, mesh wall, elastic) with `points` as its points.
ContactBody contact_body(const SceneBody& body, PointSet points);
// Whether points i and j of `body` are joined by an intact bond (BondQuery's test of a body).
bool joined_by_intact_bond(const Body& body, std::uint32_t i, std::uint32_t j);

// Writable views of every body, in scene order.
std::vector<ContactBody> contact_bodies(Scene& scene);
// Read-only views (no force_density): enough for ContactSettings::law and the stiffness bounds.
std::vector<ContactBody> contact_bodies(const Scene& scene);
// The points alone, for ContactManager::rebind; the second form refills `points` (no
// allocation in a time step once it holds every body).
std::vector<PointSet> contact_point_sets(Scene& scene);
void contact_point_sets(Scene& scene, std::vector<PointSet>& points);

// Whether any pair of the scene's bodies (a body with itself included) has a contact law.
bool has_contact_work(const Scene& scene);
// Null when the scene has no contact work to do: one body without self-contact, or no pair of
// bodies with a contact law.
std::unique_ptr<ContactManager> make_contact_manager(Scene& scene);

// The law of every interacting pair of bodies (a <= b), for the set-up report and the summary.
struct ContactLawNote {
  std::string bodies;  // "a/b"
  std::string law;
  double friction = 0;
  double damping_ratio = 0;  // the normal dashpot's gamma / (2 sqrt(k m*)); 0 for the seed law
};
std::vector<ContactLawNote> contact_law_notes(const Scene& scene);
// One line per pair that does not use the default law; empty when all do.
std::string contact_law_report(const Scene& scene);

// Per body, the contact stiffness bound its points may feel (0 without contact).
std::vector<double> contact_stiffness_bounds(const Scene& scene);

// 2 sqrt(rho / (k_i + extra)) minimised over the points of the body (Body::stiffness_bound k_i).
StableStep stable_step_with(const Body& body, double extra_stiffness);

}  // namespace ckpd
