#pragma once
// Contact as a case file asks for it: constants given globally and per body pair, and which
// bodies have self-contact; resolved into one PairLaw per interacting pair of bodies.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "bodies/body.hpp"
#include "contact/contact_law.hpp"

namespace ckpd {

// What contact needs to know of a body besides its points.
struct ContactBody {
  Body* body = nullptr;
  double spacing = 0;       // lattice spacing dx: bounds how densely its points can sit
  bool rigid = false;       // no horizon of its own (Body::horizon is 0)
  bool prescribed = false;  // its motion is imposed: two such bodies never interact
};

// Constants that may be given globally or for one pair; a pair's own value wins.
struct ContactConstants {
  std::optional<double> radius;     // l_c; default half the larger spacing of the two bodies
  std::optional<double> stiffness;  // Ccon; a pair without one (own or global) has no contact
  std::optional<double> skin;       // default: the radius
  std::optional<double> horizon;    // delta for both sides; default each receiver's own horizon
};

struct ContactPairSetting {
  std::size_t first = 0, second = 0;  // body indices, first <= second; equal: self-contact
  ContactConstants constants;
  bool enabled = true;
};

struct ContactSettings {
  bool present = false;  // the case has a `contact` section
  ContactConstants global;
  std::vector<ContactPairSetting> pairs;
  std::vector<std::size_t> self_contact;  // bodies whose own unbonded points repel (global law)

  // The law between bodies a and b (a == b: self-contact), or nullopt when they do not interact
  // (no stiffness for them, disabled, self-contact not asked for, or both prescribed). Throws
  // std::invalid_argument when the pair interacts but no horizon can be found (two rigid bodies
  // without a `horizon`).
  std::optional<PairLaw> law(const std::vector<ContactBody>& bodies, std::size_t a,
                             std::size_t b) const;
  const ContactPairSetting* pair_setting(std::size_t a, std::size_t b) const;
};

}  // namespace ckpd
