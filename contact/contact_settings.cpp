#include "contact/contact_settings.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "contact/dem_law.hpp"

namespace ckpd {

double contact_coefficient(double stiffness, double horizon) {
  return 9 * stiffness / (std::numbers::pi * std::pow(horizon, 5));
}

double pair_coefficient(double a, double b) {
  return a == b ? a : 2 * a * b / (a + b);
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
  const std::string name =
      (own && own->constants.law ? own->constants.law : global.law).value_or(kDefaultLaw);
  const LawType* type = find_law(name);
  if (!type)
    throw std::invalid_argument("unknown contact law '" + name + "' (known: " + known_laws() + ")");
  const std::optional<double> stiffness = pick(&ContactConstants::stiffness);
  if (type->needs_stiffness && !stiffness) return std::nullopt;
  PairLaw law;
  law.name = name;
  law.stiffness = stiffness.value_or(0);
  const std::optional<double> own_radius =
      own && own->constants.radius ? own->constants.radius : std::nullopt;
  if (!own_radius && (A.sphere_radius > 0 || B.sphere_radius > 0)) {
    // A DEM sphere takes part: the sum of the two sides' contact radii (contact_settings.hpp).
    auto side = [&](const ContactBody& x) {
      if (x.sphere_radius > 0) return x.sphere_radius;
      if (x.wall) return 0.0;
      return 0.5 * global.radius.value_or(kDefaultRadiusRatio * x.points.spacing);
    };
    law.side_radius[0] = side(A);
    law.side_radius[1] = side(B);
    law.radius = law.side_radius[0] + law.side_radius[1];
  } else {
    law.radius = pick(&ContactConstants::radius)
                     .value_or(kDefaultRadiusRatio * std::max(A.points.spacing, B.points.spacing));
  }
  law.skin = pick(&ContactConstants::skin).value_or(law.radius);
  // The law's parameters: the global ones it knows, overridden by the pair's own.
  LawInputs inputs;
  inputs.radius = law.radius;
  inputs.side_radius[0] = law.side_radius[0];
  inputs.side_radius[1] = law.side_radius[1];
  for (int k = 0; k < 2; ++k) {
    const ContactBody& body = k == 0 ? A : B;
    inputs.side[k] = {std::string(body.points.name), body.rigid, body.wall != nullptr,
                      body.elastic};
  }
  for (const LawParameter& parameter : type->parameters) {
    const ContactConstants* from =
        own && own->constants.parameters.count(parameter.key)
            ? &own->constants
            : (global.parameters.count(parameter.key) ? &global : nullptr);
    if (from)
      inputs.parameters[parameter.key] = from->parameters.at(parameter.key);
    else if (parameter.required)
      throw std::invalid_argument("contact law '" + name + "' needs `" + parameter.key + "` (" +
                                  parameter.expected + ")");
  }
  auto finish = [&]() -> std::optional<PairLaw> {
    inputs.coefficient = law.mean_coefficient();
    law.dem = type->make(inputs);
    return law;
  };
  if (!type->needs_stiffness) return finish();
  if (const auto h = pick(&ContactConstants::horizon)) {
    law.coefficient[0] = law.coefficient[1] = contact_coefficient(law.stiffness, *h);
    return finish();
  }
  // A rigid receiver has no horizon of its own and uses its partner's, so a rigid and a
  // deformable body always exchange equal and opposite forces.
  const double ha = A.rigid ? B.points.horizon : A.points.horizon;
  const double hb = B.rigid ? A.points.horizon : B.points.horizon;
  if (!(ha > 0) || !(hb > 0))
    throw std::invalid_argument("contact between rigid bodies '" + std::string(A.points.name) +
                                "' and '" + std::string(B.points.name) +
                                "' needs a horizon (delta of 9 Ccon/(pi delta^5)): give `horizon` "
                                "for the pair or for all contact");
  const double ca = contact_coefficient(law.stiffness, ha);
  const double cb = contact_coefficient(law.stiffness, hb);
  if (name == kOwnHorizonLaw) {
    law.coefficient[0] = ca;
    law.coefficient[1] = cb;
  } else {
    law.coefficient[0] = law.coefficient[1] = pair_coefficient(ca, cb);
  }
  return finish();
}

}  // namespace ckpd
