// `velocity_table`: a prescribed velocity given as a table of times and values, held piecewise
// constant (`interpolation: step`: values[k] from times[k] until times[k+1]) or interpolated
// linearly between the rows (`linear`, the default); before the first time the first value and
// after the last time the last value hold. Like `velocity`, on all or some components of a
// region's points. It is the case-file form of a velocity changed during a run (the Python
// module's steering).
#include <algorithm>
#include <cmath>

#include "src/engine/condition.hpp"

namespace ckpd {

namespace {

class VelocityTable : public Condition {
 public:
  VelocityTable(std::vector<std::uint32_t> points, std::vector<double> times,
                std::vector<Vec3> values, std::uint8_t components, bool linear)
      : times_(std::move(times)),
        values_(std::move(values)),
        components_(components),
        linear_(linear) {
    points_ = std::move(points);
  }
  std::uint8_t prescribed_components() const override { return components_; }
  double prescribed_velocity(int c, double t) const override {
    const std::size_t k = row(t);
    if (!linear_ || k + 1 == times_.size() || t < times_[k]) return values_[k][c];
    const double f = (t - times_[k]) / (times_[k + 1] - times_[k]);
    return values_[k][c] + f * (values_[k + 1][c] - values_[k][c]);
  }
  double prescribed_acceleration(int c, double t) const override {
    const std::size_t k = row(t);
    if (!linear_ || k + 1 == times_.size() || t < times_[k]) return 0.0;
    return (values_[k + 1][c] - values_[k][c]) / (times_[k + 1] - times_[k]);
  }
  void initialise(Body& body) const override {
    for (std::uint32_t i : points_)
      for (int c = 0; c < 3; ++c)
        if (components_ & (1u << c)) body.velocity[i][c] = prescribed_velocity(c, 0.0);
  }
  double max_speed() const override {
    double s = 0;
    for (const Vec3& v : values_) s = std::max(s, v.norm());
    return s;
  }

 private:
  // The last row whose time is <= t (row 0 before the first time).
  std::size_t row(double t) const {
    const auto it = std::upper_bound(times_.begin(), times_.end(), t);
    return it == times_.begin() ? 0 : static_cast<std::size_t>(it - times_.begin()) - 1;
  }

  std::vector<double> times_;
  std::vector<Vec3> values_;
  std::uint8_t components_;
  bool linear_;
};

const bool registered =
    register_condition("velocity_table", [](const CaseNode& n, const ConditionTarget& t) {
      const int dim = t.body.dimension;
      auto points = select_points(n.optional("region"), t);
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
      bool linear = true;
      if (auto i = n.optional("interpolation")) {
        const std::string mode = i->as_string();
        if (mode != "linear" && mode != "step") i->fail("linear or step");
        linear = mode == "linear";
      }
      const std::uint8_t components = read_prescribed_components(n.optional("components"), dim);
      return std::unique_ptr<Condition>(new VelocityTable(std::move(points), std::move(times),
                                                          std::move(values), components, linear));
    });

}  // namespace

}  // namespace ckpd
