#pragma once
// Shapes select points: a body's geometry (sampled on a lattice) and the regions that
// conditions, no-failure zones and outputs act on. Each shape is one small class registered by
// its `type` name; adding one touches no other file.
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "bodies/vec.hpp"
#include "src/input/case_node.hpp"

namespace ckpd {

struct Bounds {
  Vec3 lo, hi;
  bool finite() const { return lo.allFinite() && hi.allFinite(); }
};

class Shape {
 public:
  virtual ~Shape() = default;
  virtual bool contains(const Vec3& p) const = 0;
  // Axis-aligned bounds; infinite for unbounded shapes (a half-space).
  virtual Bounds bounds() const = 0;
};

// Shapes (bodies, obstacles, regions) lie within this distance of the origin, in m.
inline constexpr double kMaxCoordinate = 1e6;

using ShapeFactory = std::function<std::unique_ptr<Shape>(const CaseNode&, int dimension)>;

// Registry: `register_shape("box", factory)` from the shape's own file.
std::map<std::string, ShapeFactory>& shape_registry();
bool register_shape(const std::string& type, ShapeFactory factory);

// Reads `{type: NAME, ...}` and builds the shape; unknown types and keys are errors.
std::unique_ptr<Shape> make_shape(const CaseNode& node, int dimension);

}  // namespace ckpd
