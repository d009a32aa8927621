#include "src/engine/time_table.hpp"

#include <algorithm>
#include <cmath>

namespace ckpd {

TimeTable::TimeTable(std::vector<double> time, std::vector<Vec3> value, Interpolation interpolation)
    : time_(std::move(time)), value_(std::move(value)), interpolation_(interpolation) {}

std::size_t TimeTable::interval(double t) const {
  const auto after = std::upper_bound(time_.begin(), time_.end(), t);
  return static_cast<std::size_t>(after - time_.begin()) - 1;
}

Vec3 TimeTable::value(double t) const {
  if (constant() || t <= time_.front()) return value_.front();
  if (t >= time_.back()) return value_.back();
  const std::size_t k = interval(t);
  if (interpolation_ == Interpolation::step) return value_[k];
  const double w = (t - time_[k]) / (time_[k + 1] - time_[k]);
  return (1 - w) * value_[k] + w * value_[k + 1];
}

Vec3 TimeTable::rate(double t) const {
  if (constant() || interpolation_ == Interpolation::step || t < time_.front() || t >= time_.back())
    return Vec3::Zero();
  const std::size_t k = interval(t);
  return (value_[k + 1] - value_[k]) / (time_[k + 1] - time_[k]);
}

double TimeTable::max_norm() const {
  double m = 0;
  for (const Vec3& v : value_) m = std::max(m, v.norm());
  return m;
}

namespace {

TimeTable read_table(const CaseNode& node, int components) {
  const CaseNode rows = node.required("table");
  Interpolation interpolation = Interpolation::linear;
  if (auto i = node.optional("interpolation")) {
    const std::string mode = i->as_string();
    if (mode != "linear" && mode != "step") i->fail("linear or step");
    interpolation = mode == "step" ? Interpolation::step : Interpolation::linear;
  }
  node.finish();
  std::vector<double> time;
  std::vector<Vec3> value;
  const std::string row_form = components == 1   ? "[t, v]"
                               : components == 2 ? "[t, vx, vy]"
                                                 : "[t, vx, vy, vz]";
  for (const CaseNode& row : rows.elements()) {
    if (!row.is_sequence() || row.yaml().size() != static_cast<std::size_t>(components + 1))
      row.fail("a row " + row_form);
    const std::vector<double> numbers = row.as_doubles();
    if (!time.empty() && !(numbers[0] > time.back()))
      row.fail("a time after the previous row's (" + std::to_string(time.back()) + " s)");
    time.push_back(numbers[0]);
    Vec3 v = Vec3::Zero();
    for (int c = 0; c < components; ++c) v[c] = numbers[static_cast<std::size_t>(c) + 1];
    value.push_back(v);
  }
  if (time.empty()) rows.fail("at least one row " + row_form);
  return TimeTable(std::move(time), std::move(value), interpolation);
}

}  // namespace

TimeTable read_vector_value(const CaseNode& node, int dimension) {
  if (node.is_map()) return read_table(node, dimension);
  return TimeTable(node.as_vector(dimension));
}

TimeTable read_scalar_value(const CaseNode& node) {
  if (node.is_map()) return read_table(node, 1);
  return TimeTable(Vec3(node.as_double(), 0, 0));
}

}  // namespace ckpd
