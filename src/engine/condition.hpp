#pragma once
// Initial and boundary conditions and loads (THEORY.md section 7). Each is one small class,
// registered by its `type` name in its own file (like a LAMMPS fix); the case loader builds them
// generically and the time integrator calls them through this interface, once per condition and
// step, never per point through a virtual call.
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "bodies/body.hpp"
#include "src/input/case_node.hpp"

namespace ckpd {

// What a factory needs to know about the body a condition acts on.
struct ConditionTarget {
  const Body& body;
  double spacing;  // lattice spacing dx of the body
};

class Condition {
 public:
  virtual ~Condition() = default;
  // The points it acts on (selected once, in the reference configuration).
  const std::vector<std::uint32_t>& points() const { return points_; }
  // For a rank holding the body restricted to some of its points (src/engine/distribution.hpp):
  // `kept` are the restriction's indices in the whole body, increasing; the condition's points
  // become the local indices of those it keeps, the others are dropped.
  void restrict_points(const std::vector<std::uint32_t>& kept);
  // Once, before the first force evaluation.
  virtual void initialise(Body&) const {}
  // Adds its external force density at time t to body.external_force_density.
  virtual void add_external_force(Body&, double /*t*/) const {}
  // Bit c set: this condition prescribes the motion of component c of its points.
  virtual std::uint8_t prescribed_components() const { return 0; }
  // Whether the prescription holds at time t (a velocity with a `duration` lets its points go
  // after it; they then move under their forces).
  virtual bool prescribes_at(double /*t*/) const { return true; }
  // Prescribed velocity and acceleration of component c at time t (for prescribed components).
  virtual double prescribed_velocity(int /*component*/, double /*t*/) const { return 0; }
  virtual double prescribed_acceleration(int /*component*/, double /*t*/) const { return 0; }
  // The largest speed this condition imposes (for the instability guard's speed limit).
  virtual double max_speed() const { return 0; }
  // The value a controller may change between steps (the Python module's steering): a
  // prescribed velocity's `value`. Conditions without one refuse (std::invalid_argument). The
  // instability guard's speed limit stays the one set from the case.
  virtual bool has_value() const { return false; }
  virtual Vec3 value() const { return Vec3::Zero(); }
  virtual void set_value(const Vec3&) {
    throw std::invalid_argument("this condition has no value that can be changed");
  }
  // "case.yaml:12: conditions[0]", for errors about what the condition asks (make_condition).
  const std::string& where() const { return where_; }
  void set_where(std::string where) { where_ = std::move(where); }
  // How long it acts from t = 0 (a pulse's length, a velocity's `duration`; infinite for the
  // others) and where the case sets that ("case.yaml:14: conditions[0].duration"). The run
  // refuses a duration no step after t = 0 falls in (src/engine/simulation.cpp): a pulse that
  // short would put in no load at all.
  double duration() const { return duration_; }
  const std::string& duration_where() const { return duration_where_; }
  void set_duration(double seconds, std::string where) {
    duration_ = seconds;
    duration_where_ = std::move(where);
  }

 protected:
  std::vector<std::uint32_t> points_;

 private:
  std::string where_;
  double duration_ = std::numeric_limits<double>::infinity();
  std::string duration_where_;
};

using ConditionFactory =
    std::function<std::unique_ptr<Condition>(const CaseNode&, const ConditionTarget&)>;
std::map<std::string, ConditionFactory>& condition_registry();
bool register_condition(const std::string& type, ConditionFactory factory);

// Builds the condition described by `node` (its `type` and its own keys; `body` has been read
// by the caller). Unknown types and keys are errors.
std::unique_ptr<Condition> make_condition(const CaseNode& node, const ConditionTarget& target);

// The points of `body` whose reference position lies in the shape given by `region` (all points
// when `region` is absent). An empty selection is an error: a condition that acts on nothing is
// almost always a misplaced region.
std::vector<std::uint32_t> select_points(const std::optional<CaseNode>& region,
                                         const ConditionTarget& target);

// The `components` of a prescribed motion (x, y, z): a bit mask, all components when absent.
std::uint8_t read_prescribed_components(const std::optional<CaseNode>& node, int dimension);

}  // namespace ckpd
