#pragma once
// Ties a scene's bodies to the contact library: which bodies take part and how, the contact
// manager a run needs (none when no two bodies interact and no body has self-contact), and the
// stable-step estimate with the contact stiffness added (contact_stiffness.hpp).
#include <memory>
#include <vector>

#include "bodies/body.hpp"
#include "contact/contact_manager.hpp"
#include "src/engine/scene.hpp"

namespace ckpd {

std::vector<ContactBody> contact_bodies(Scene& scene);

// Null when the scene has no contact work to do: one body without self-contact, or no pair of
// bodies with a contact law.
std::unique_ptr<ContactManager> make_contact_manager(Scene& scene);

// Per body, the contact stiffness bound its points may feel (0 without contact).
std::vector<double> contact_stiffness_bounds(const Scene& scene);

// 2 sqrt(rho / (k_i + extra)) minimised over the points of the body (Body::stiffness_bound k_i).
StableStep stable_step_with(const Body& body, double extra_stiffness);

}  // namespace ckpd
