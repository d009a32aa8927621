#include "contact/dem_law.hpp"

#include <stdexcept>

namespace ckpd {

std::map<std::string, LawType>& law_registry() {
  static std::map<std::string, LawType> registry;
  return registry;
}

bool register_law(const std::string& name, LawType type) {
  law_registry()[name] = std::move(type);
  return true;
}

std::string known_laws() {
  std::string names;
  for (const auto& [name, type] : law_registry()) names += (names.empty() ? "" : ", ") + name;
  return names;
}

const LawType* find_law(const std::string& name) {
  const auto it = law_registry().find(name);
  return it == law_registry().end() ? nullptr : &it->second;
}

bool valid_restitution(double e) {
  return e > 0 && e <= 1;
}
bool valid_non_negative(double x) {
  return x >= 0;
}
bool valid_positive(double x) {
  return x > 0;
}
bool valid_poisson(double x) {
  return x > -1 && x < 0.5;
}

LawParameter restitution_parameter() {
  return {"restitution", "a coefficient of restitution e in (0, 1]", true, 1, valid_restitution};
}

LawParameter friction_parameter() {
  return {"friction", "a Coulomb friction coefficient mu >= 0", false, 1, valid_non_negative};
}

double side_value(const LawInputs& in, const std::string& key, std::size_t side) {
  const auto it = in.parameters.find(key);
  if (it == in.parameters.end() || it->second.empty())
    throw std::invalid_argument("the law needs `" + key + "`");
  return it->second.size() == 1 ? it->second[0] : it->second.at(side);
}

double value_or(const LawInputs& in, const std::string& key, double fallback) {
  const auto it = in.parameters.find(key);
  return it == in.parameters.end() || it->second.empty() ? fallback : it->second[0];
}

}  // namespace ckpd
