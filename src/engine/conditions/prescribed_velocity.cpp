// `velocity`: prescribed velocity on a region, constant or ramped linearly from 0 over
// `ramp_time` (MODEL.md section 7), on all or some components. `fixed`: zero velocity.
#include <algorithm>
#include <cmath>

#include "src/engine/condition.hpp"

namespace ckpd {

namespace {

class PrescribedVelocity : public Condition {
 public:
  PrescribedVelocity(std::vector<std::uint32_t> points, Vec3 value, std::uint8_t components,
                     double ramp_time)
      : value_(value), components_(components), ramp_time_(ramp_time) {
    points_ = std::move(points);
  }
  std::uint8_t prescribed_components() const override { return components_; }
  double prescribed_velocity(int c, double t) const override {
    return ramp_time_ > 0 ? value_[c] * std::min(t / ramp_time_, 1.0) : value_[c];
  }
  double prescribed_acceleration(int c, double t) const override {
    return ramp_time_ > 0 && t < ramp_time_ ? value_[c] / ramp_time_ : 0.0;
  }
  void initialise(Body& body) const override {
    for (std::uint32_t i : points_)
      for (int c = 0; c < 3; ++c)
        if (components_ & (1u << c)) body.velocity[i][c] = prescribed_velocity(c, 0.0);
  }
  double max_speed() const override { return value_.norm(); }

 private:
  Vec3 value_;
  std::uint8_t components_;
  double ramp_time_;
};

std::uint8_t read_components(const std::optional<CaseNode>& node, int dimension) {
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

const bool velocity_registered =
    register_condition("velocity", [](const CaseNode& n, const ConditionTarget& t) {
      const int dim = t.body.dimension;
      auto points = select_points(n.optional("region"), t);
      const Vec3 value =
          n.required("value").as_vector_below(dim, CaseNode::kMaxSpeed, "a velocity in m/s");
      const std::uint8_t components = read_components(n.optional("components"), dim);
      double ramp = 0;
      if (auto r = n.optional("ramp_time")) ramp = r->as_non_negative();
      return std::unique_ptr<Condition>(
          new PrescribedVelocity(std::move(points), value, components, ramp));
    });

const bool fixed_registered =
    register_condition("fixed", [](const CaseNode& n, const ConditionTarget& t) {
      const int dim = t.body.dimension;
      auto points = select_points(n.optional("region"), t);
      const std::uint8_t components = read_components(n.optional("components"), dim);
      return std::unique_ptr<Condition>(
          new PrescribedVelocity(std::move(points), Vec3::Zero(), components, 0.0));
    });

}  // namespace

}  // namespace ckpd
