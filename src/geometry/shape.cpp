#include "src/geometry/shape.hpp"

#include <cmath>
#include <sstream>

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
  // Coordinates far from the origin lose the spacing to round-off and overflow the broad
  // phase's arithmetic (FCL crashed on a sphere centred at 1e200). Unbounded directions (a
  // half-space) are infinite by design and pass.
  const Bounds b = shape->bounds();
  for (int d = 0; d < 3; ++d)
    for (const double v : {b.lo[d], b.hi[d]})
      if (std::isnan(v) || (std::isfinite(v) && std::abs(v) > kMaxCoordinate)) {
        std::ostringstream msg;
        msg << "a shape within " << kMaxCoordinate << " m of the origin (its bounds reach " << v
            << " m)";
        node.fail(msg.str());
      }
  return shape;
}

}  // namespace ckpd
