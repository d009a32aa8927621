#include "src/case/material_model.hpp"

#include <cmath>

namespace ckpd {

double strain_measure_of(const CaseNode& m, double fallback) {
  auto sm = m.optional("strain_measure");
  if (!sm) return fallback;
  if (!sm->is_map()) sm->fail("a map {m: M} (the Seth-Hill exponent, e.g. {m: 0})");
  const CaseNode exponent = sm->required("m");
  // The named measures lie in [-1, 1] (Almansi, log, Biot, Green). A stiffness growing as
  // r^(4m - 2) makes any larger |m| overflow at strains a run meets: m = 1e6 gave null energies.
  const double value = exponent.as_double();
  if (!(std::abs(value) <= kMaxStrainMeasure))
    exponent.fail("a Seth-Hill exponent m from -2 to 2 (0.5 is l/L - 1, 0 is log, 1 Green's)");
  sm->finish();
  return value;
}

std::map<std::string, MaterialFactory>& material_registry() {
  static std::map<std::string, MaterialFactory> registry;
  return registry;
}

bool register_material_model(const std::string& model, MaterialFactory factory) {
  material_registry()[model] = std::move(factory);
  return true;
}

std::unique_ptr<MaterialModel> make_material(const CaseNode& node) {
  const auto& registry = material_registry();
  std::string model = "ckpd";
  const std::optional<CaseNode> model_node = node.optional("model");
  if (model_node) model = model_node->as_string();
  const auto it = registry.find(model);
  if (it == registry.end()) {
    std::string known;
    for (const auto& [name, f] : registry) known += (known.empty() ? "" : ", ") + name;
    model_node->fail("a force model (" + known + ")");
  }
  std::unique_ptr<MaterialModel> m = it->second(node);
  node.finish();
  return m;
}

}  // namespace ckpd
