#include "contact/contact_settings.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace ckpd {

double contact_coefficient(double stiffness, double horizon) {
  return 9 * stiffness / (std::numbers::pi * std::pow(horizon, 5));
}

const ContactPairSetting* ContactSettings::pair_setting(std::size_t a, std::size_t b) const {
  if (a > b) std::swap(a, b);
  for (const ContactPairSetting& p : pairs)
    if (p.first == a && p.second == b) return &p;
  return nullptr;
}

std::optional<PairLaw> ContactSettings::law(const std::vector<ContactBody>& bodies, std::size_t a,
                                            std::size_t b) const {
  if (!present) return std::nullopt;
  const ContactPairSetting* own = pair_setting(a, b);
  if (own && !own->enabled) return std::nullopt;
  if (a == b && !own &&
      std::find(self_contact.begin(), self_contact.end(), a) == self_contact.end())
    return std::nullopt;
  const ContactBody& A = bodies[a];
  const ContactBody& B = bodies[b];
  if (A.prescribed && B.prescribed) return std::nullopt;
  auto pick = [&](std::optional<double> ContactConstants::*field) {
    return own && (own->constants.*field) ? own->constants.*field : global.*field;
  };
  const std::optional<double> stiffness = pick(&ContactConstants::stiffness);
  if (!stiffness) return std::nullopt;
  PairLaw law;
  law.stiffness = *stiffness;
  law.radius = pick(&ContactConstants::radius)
                   .value_or(kDefaultRadiusRatio * std::max(A.spacing, B.spacing));
  law.skin = pick(&ContactConstants::skin).value_or(law.radius);
  if (const auto h = pick(&ContactConstants::horizon)) {
    law.coefficient[0] = law.coefficient[1] = contact_coefficient(law.stiffness, *h);
    return law;
  }
  // A rigid receiver has no horizon of its own and uses its partner's, so a rigid and a
  // deformable body always exchange equal and opposite forces.
  const double ha = A.rigid ? B.body->horizon : A.body->horizon;
  const double hb = B.rigid ? A.body->horizon : B.body->horizon;
  if (!(ha > 0) || !(hb > 0))
    throw std::invalid_argument("contact between rigid bodies '" + A.body->name + "' and '" +
                                B.body->name + "' needs a horizon (delta of 9 Ccon/(pi delta^5))");
  law.coefficient[0] = contact_coefficient(law.stiffness, ha);
  law.coefficient[1] = contact_coefficient(law.stiffness, hb);
  return law;
}

}  // namespace ckpd
