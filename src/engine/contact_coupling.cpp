#include "src/engine/contact_coupling.hpp"

#include <cmath>

#include "contact/contact_stiffness.hpp"

namespace ckpd {

std::vector<ContactBody> contact_bodies(Scene& scene) {
  std::vector<ContactBody> bodies;
  for (SceneBody& sb : scene.bodies)
    bodies.push_back({&sb.body, sb.spacing, sb.rigid.has_value(),
                      sb.rigid.has_value() && sb.rigid->prescribed(), sb.wall.get()});
  return bodies;
}

std::unique_ptr<ContactManager> make_contact_manager(Scene& scene) {
  if (!scene.contact.present) return nullptr;
  std::vector<ContactBody> bodies = contact_bodies(scene);
  bool any = false;
  for (std::size_t a = 0; a < bodies.size() && !any; ++a)
    for (std::size_t b = a; b < bodies.size() && !any; ++b)
      any = scene.contact.law(bodies, a, b).has_value();
  if (!any) return nullptr;
  return std::make_unique<ContactManager>(std::move(bodies), scene.contact);
}

std::vector<double> contact_stiffness_bounds(const Scene& scene) {
  // The contact library reads the bodies only; the pointers are not kept.
  return contact_stiffness_bounds(scene.contact, contact_bodies(const_cast<Scene&>(scene)));
}

StableStep stable_step_with(const Body& body, double extra_stiffness) {
  StableStep s;
  for (std::size_t i = 0; i < body.size(); ++i) {
    const double k = body.stiffness_bound[i] + extra_stiffness;
    if (k <= 0) continue;
    const double dt = 2.0 * std::sqrt(body.density / k);
    if (dt < s.dt) s = {dt, i};
  }
  return s;
}

}  // namespace ckpd
