// `velocity`: prescribed velocity on a region, constant or ramped linearly from 0 over
// `ramp_time` (THEORY.md section 7), or tabulated over time (`value: {table: [[t, vx, vy, vz],
// ...], interpolation: linear | step}`, src/engine/time_table.hpp), on all or some components;
// with `duration`, only for 0 <= t <= duration (then the points move under their forces: a
// finite pulse).
// `fixed`: zero velocity. `velocity_table` (`times`, `values`, `interpolation`) is the same
// condition as a `velocity` with a table value, spelt as the Python examples first wrote it.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "src/engine/condition.hpp"
#include "src/engine/time_table.hpp"

namespace ckpd {

namespace {

class PrescribedVelocity : public Condition {
 public:
  PrescribedVelocity(std::vector<std::uint32_t> points, TimeTable value, std::uint8_t components,
                     double ramp_time, bool steerable,
                     double duration = std::numeric_limits<double>::infinity())
      : value_(std::move(value)),
        components_(components),
        ramp_time_(ramp_time),
        duration_(duration),
        steerable_(steerable) {
    points_ = std::move(points);
  }
  std::uint8_t prescribed_components() const override { return components_; }
  bool prescribes_at(double t) const override { return t <= duration_; }
  double prescribed_velocity(int c, double t) const override {
    const double v = value_.value(t)[c];
    return ramp_time_ > 0 ? v * std::min(t / ramp_time_, 1.0) : v;
  }
  double prescribed_acceleration(int c, double t) const override {
    if (ramp_time_ > 0) return t < ramp_time_ ? value_.value(t)[c] / ramp_time_ : 0.0;
    return value_.rate(t)[c];
  }
  void initialise(Body& body) const override {
    for (std::uint32_t i : points_)
      for (int c = 0; c < 3; ++c)
        if (components_ & (1u << c)) body.velocity[i][c] = prescribed_velocity(c, 0.0);
  }
  double max_speed() const override { return value_.max_norm(); }
  // Only a constant `velocity` takes a new value (`fixed` holds its points still; a table is the
  // case's own schedule); a new value replaces the constant.
  bool has_value() const override { return steerable_ && value_.constant(); }
  Vec3 value() const override { return value_.value(0.0); }
  void set_value(const Vec3& value) override {
    if (!has_value()) Condition::set_value(value);
    value_ = TimeTable(value);
  }

 private:
  TimeTable value_;
  std::uint8_t components_;
  double ramp_time_;
  double duration_;  // s: prescribed for 0 <= t <= duration_, free after
  bool steerable_;
};

const bool velocity_registered =
    register_condition("velocity", [](const CaseNode& n, const ConditionTarget& t) {
      const int dim = t.body.dimension;
      auto points = select_points(n.optional("region"), t);
      const CaseNode value_node = n.required("value");
      TimeTable value = read_vector_value(value_node, dim);
      if (!(value.max_norm() < CaseNode::kMaxSpeed)) {
        std::ostringstream s;
        s << "a velocity in m/s of magnitude below " << CaseNode::kMaxSpeed << " (got "
          << value.max_norm() << ")";
        value_node.fail(s.str());
      }
      const std::uint8_t components = read_prescribed_components(n.optional("components"), dim);
      double ramp = 0;
      if (auto r = n.optional("ramp_time")) {
        ramp = r->as_non_negative();
        if (!value.constant())
          r->fail("no ramp_time with a table value (put the ramp in the table)");
      }
      double duration = std::numeric_limits<double>::infinity();
      std::string duration_where;
      if (auto d = n.optional("duration")) {
        duration = d->as_positive();
        duration_where = d->where();
        if (!(duration > ramp))
          d->fail("a duration in s longer than the ramp_time (" + std::to_string(ramp) + " s)");
      }
      auto velocity = std::unique_ptr<Condition>(new PrescribedVelocity(
          std::move(points), std::move(value), components, ramp, true, duration));
      if (!duration_where.empty()) velocity->set_duration(duration, duration_where);
      return velocity;
    });

// `times` and `values` as a velocity's table (the `velocity_table` spelling).
TimeTable read_times_and_values(const CaseNode& n, int dim) {
  const CaseNode times_node = n.required("times");
  std::vector<double> times;
  for (const CaseNode& e : times_node.elements()) {
    const double time = e.as_non_negative();
    if (!times.empty() && time <= times.back()) e.fail("a time above the one before it");
    times.push_back(time);
  }
  if (times.empty()) times_node.fail("at least one time");
  const CaseNode values_node = n.required("values");
  std::vector<Vec3> values;
  for (const CaseNode& e : values_node.elements()) values.push_back(e.as_vector(dim));
  if (values.size() != times.size())
    values_node.fail("one value per time (" + std::to_string(times.size()) + ")");
  Interpolation interpolation = Interpolation::linear;
  if (auto i = n.optional("interpolation")) {
    const std::string mode = i->as_string();
    if (mode != "linear" && mode != "step") i->fail("linear or step");
    interpolation = mode == "step" ? Interpolation::step : Interpolation::linear;
  }
  TimeTable table(std::move(times), std::move(values), interpolation);
  if (!(table.max_norm() < CaseNode::kMaxSpeed)) {
    std::ostringstream s;
    s << "velocities in m/s of magnitude below " << CaseNode::kMaxSpeed << " (got "
      << table.max_norm() << ")";
    values_node.fail(s.str());
  }
  return table;
}

const bool table_registered =
    register_condition("velocity_table", [](const CaseNode& n, const ConditionTarget& t) {
      const int dim = t.body.dimension;
      auto points = select_points(n.optional("region"), t);
      TimeTable value = read_times_and_values(n, dim);
      const std::uint8_t components = read_prescribed_components(n.optional("components"), dim);
      return std::unique_ptr<Condition>(
          new PrescribedVelocity(std::move(points), std::move(value), components, 0.0, true));
    });

const bool fixed_registered =
    register_condition("fixed", [](const CaseNode& n, const ConditionTarget& t) {
      const int dim = t.body.dimension;
      auto points = select_points(n.optional("region"), t);
      const std::uint8_t components = read_prescribed_components(n.optional("components"), dim);
      return std::unique_ptr<Condition>(new PrescribedVelocity(
          std::move(points), TimeTable(Vec3::Zero()), components, 0.0, false));
    });

}  // namespace

}  // namespace ckpd
