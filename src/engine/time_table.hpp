#pragma once
// A condition's value over time: a constant, or `{table: [[t, v...], ...]}` with times strictly
// increasing, interpolated linearly between rows (`interpolation: linear`, the default) or held
// piecewise constant (`interpolation: step`: row k's value from its time until row k + 1's), and
// held at the first and last rows' values outside them. A row holds the time and one number (a
// scalar value: a pressure) or one per component of the body's dimension (a vector value: a
// velocity, an acceleration).
#include <optional>
#include <vector>

#include "bodies/vec.hpp"
#include "src/input/case_node.hpp"

namespace ckpd {

enum class Interpolation { linear, step };

class TimeTable {
 public:
  TimeTable() = default;
  explicit TimeTable(Vec3 constant) : time_{0}, value_{constant} {}
  TimeTable(std::vector<double> time, std::vector<Vec3> value,
            Interpolation interpolation = Interpolation::linear);

  Vec3 value(double t) const;
  // d value / dt (the slope of the row interval holding t; 0 outside the table and for a step
  // table, whose jumps the velocity takes without an acceleration).
  Vec3 rate(double t) const;
  // The largest |value| over the table (its maximum is at a row).
  double max_norm() const;
  bool constant() const { return time_.size() <= 1; }

 private:
  std::size_t interval(double t) const;  // k with time_[k] <= t < time_[k + 1]
  std::vector<double> time_;
  std::vector<Vec3> value_;
  Interpolation interpolation_ = Interpolation::linear;
};

// `node` is a list of `dimension` numbers (a constant) or {table: [[t, v_1, .., v_dim], ...],
// interpolation: linear | step}.
TimeTable read_vector_value(const CaseNode& node, int dimension);
// `node` is a number or {table: [[t, v], ...]}; the value is in the table's x component.
TimeTable read_scalar_value(const CaseNode& node);

}  // namespace ckpd
