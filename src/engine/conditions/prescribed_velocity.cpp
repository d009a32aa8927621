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
                     double ramp_time, bool steerable)
      : value_(value), components_(components), ramp_time_(ramp_time), steerable_(steerable) {
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
  // `fixed` holds its points still: only `velocity` takes a new value.
  bool has_value() const override { return steerable_; }
  Vec3 value() const override { return value_; }
  void set_value(const Vec3& value) override {
    if (!steerable_) Condition::set_value(value);
    value_ = value;
  }

 private:
  Vec3 value_;
  std::uint8_t components_;
  double ramp_time_;
  bool steerable_;
};

const bool velocity_registered =
    register_condition("velocity", [](const CaseNode& n, const ConditionTarget& t) {
      const int dim = t.body.dimension;
      auto points = select_points(n.optional("region"), t);
      const Vec3 value = n.required("value").as_vector(dim);
      const std::uint8_t components = read_prescribed_components(n.optional("components"), dim);
      double ramp = 0;
      if (auto r = n.optional("ramp_time")) ramp = r->as_non_negative();
      return std::unique_ptr<Condition>(
          new PrescribedVelocity(std::move(points), value, components, ramp, true));
    });

const bool fixed_registered =
    register_condition("fixed", [](const CaseNode& n, const ConditionTarget& t) {
      const int dim = t.body.dimension;
      auto points = select_points(n.optional("region"), t);
      const std::uint8_t components = read_prescribed_components(n.optional("components"), dim);
      return std::unique_ptr<Condition>(
          new PrescribedVelocity(std::move(points), Vec3::Zero(), components, 0.0, false));
    });

}  // namespace

}  // namespace ckpd
