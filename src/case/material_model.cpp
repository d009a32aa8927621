#include "src/case/material_model.hpp"

namespace ckpd {

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
