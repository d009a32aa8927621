#include "src/geometry/shape.hpp"

namespace ckpd {

std::map<std::string, ShapeFactory>& shape_registry() {
  static std::map<std::string, ShapeFactory> registry;
  return registry;
}

bool register_shape(const std::string& type, ShapeFactory factory) {
  shape_registry()[type] = std::move(factory);
  return true;
}

std::unique_ptr<Shape> make_shape(const CaseNode& node, int dimension) {
  const CaseNode type = node.required("type");
  const auto& registry = shape_registry();
  const auto it = registry.find(type.as_string());
  if (it == registry.end()) {
    std::string known;
    for (const auto& [name, f] : registry) known += (known.empty() ? "" : ", ") + name;
    type.fail("a shape type (" + known + ")");
  }
  std::unique_ptr<Shape> shape = it->second(node, dimension);
  node.finish();
  return shape;
}

}  // namespace ckpd
