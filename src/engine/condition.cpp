#include "src/engine/condition.hpp"

#include <algorithm>

#include "src/geometry/shape.hpp"

namespace ckpd {

void Condition::restrict_points(const std::vector<std::uint32_t>& kept) {
  std::size_t local = 0;
  for (const std::uint32_t p : points_) {
    const auto at = std::lower_bound(kept.begin(), kept.end(), p);
    if (at != kept.end() && *at == p)
      points_[local++] = static_cast<std::uint32_t>(at - kept.begin());
  }
  points_.resize(local);
}

std::map<std::string, ConditionFactory>& condition_registry() {
  static std::map<std::string, ConditionFactory> registry;
  return registry;
}

bool register_condition(const std::string& type, ConditionFactory factory) {
  condition_registry()[type] = std::move(factory);
  return true;
}

std::unique_ptr<Condition> make_condition(const CaseNode& node, const ConditionTarget& target) {
  const CaseNode type = node.required("type");
  const auto& registry = condition_registry();
  const auto it = registry.find(type.as_string());
  if (it == registry.end()) {
    std::string known;
    for (const auto& [name, f] : registry) known += (known.empty() ? "" : ", ") + name;
    type.fail("a condition type (" + known + ")");
  }
  std::unique_ptr<Condition> c = it->second(node, target);
  node.finish();
  c->set_where(node.where());
  return c;
}

std::vector<std::uint32_t> select_points(const std::optional<CaseNode>& region,
                                         const ConditionTarget& target) {
  const Body& body = target.body;
  std::vector<std::uint32_t> points;
  if (!region) {
    points.resize(body.size());
    for (std::size_t i = 0; i < body.size(); ++i) points[i] = static_cast<std::uint32_t>(i);
    return points;
  }
  const std::unique_ptr<Shape> shape = make_shape(*region, body.dimension);
  for (std::size_t i = 0; i < body.size(); ++i)
    if (shape->contains(body.reference_position[i]))
      points.push_back(static_cast<std::uint32_t>(i));
  if (points.empty())
    throw CaseError(region->where() + ": the region holds no point of body '" + body.name + "'");
  return points;
}

std::uint8_t read_prescribed_components(const std::optional<CaseNode>& node, int dimension) {
  const std::uint8_t all = dimension == 3 ? 0b111 : 0b011;
  if (!node) return all;
  std::uint8_t mask = 0;
  for (const CaseNode& e : node->elements()) {
    const std::string name = e.as_string();
    const int c = name == "x" ? 0 : name == "y" ? 1 : name == "z" && dimension == 3 ? 2 : -1;
    if (c < 0) e.fail(dimension == 3 ? "x, y or z" : "x or y");
    mask |= static_cast<std::uint8_t>(1u << c);
  }
  if (!mask) node->fail("at least one component");
  return mask;
}

}  // namespace ckpd
