// `pressure_pulse`: the body-force pulse of THEORY.md section 7 on a layer of points,
// b_ext = p(t)/dx n with p(t) = -4 p0/t1^2 (t - t1/2)^2 + p0 for t <= t1, else 0. `peak` is p0
// (N/m in 2D, N/m^2 in 3D), `duration` t1, `direction` n (normalised here).
#include "src/engine/condition.hpp"
#include "src/engine/time_table.hpp"

namespace ckpd {

namespace {

class BodyForcePulse : public Condition {
 public:
  BodyForcePulse(std::vector<std::uint32_t> points, double peak, double duration, Vec3 direction,
                 double spacing)
      : peak_(peak), duration_(duration), direction_(direction.normalized()), spacing_(spacing) {
    points_ = std::move(points);
  }
  void add_external_force(Body& body, double t) const override {
    if (t > duration_) return;
    // p0 (1 - (2h / t1)^2) with h = t - t1/2, as 4 p0 u (1 - u) with u = t / t1 in [0, 1]:
    // finite for every t1 > 0 (p0 / t1^2 is infinite below t1 = 1e-154, and infinity x 0 NaN).
    const double u = t / duration_;
    const double p = 4 * peak_ * u * (1 - u);
    const Vec3 b = (p / spacing_) * direction_;
    for (std::uint32_t i : points_) body.external_force_density[i] += b;
  }

 private:
  double peak_, duration_;
  Vec3 direction_;
  double spacing_;
};

const bool registered =
    register_condition("pressure_pulse", [](const CaseNode& n, const ConditionTarget& t) {
      const int dim = t.body.dimension;
      auto points = select_points(n.optional("region"), t);
      const double peak = n.required("peak").as_double();
      const CaseNode duration_node = n.required("duration");
      const double duration = duration_node.as_positive();
      const CaseNode dn = n.required("direction");
      const Vec3 direction = dn.as_vector(dim);
      if (direction.norm() == 0) dn.fail("a non-zero direction");
      auto pulse = std::unique_ptr<Condition>(
          new BodyForcePulse(std::move(points), peak, duration, direction, t.spacing));
      pulse->set_duration(duration, duration_node.where());
      return pulse;
    });

const bool gravity_registered = register_condition("gravity", [](const CaseNode& n,
                                                                 const ConditionTarget& t) {
  // A uniform acceleration g (constant or tabulated over time): body force density rho g on
  // every point (or a region).
  class Gravity : public Condition {
   public:
    Gravity(std::vector<std::uint32_t> p, TimeTable g, double density)
        : g_(std::move(g)), density_(density) {
      points_ = std::move(p);
    }
    void add_external_force(Body& body, double time) const override {
      const Vec3 b = density_ * g_.value(time);
      for (std::uint32_t i : points_) body.external_force_density[i] += b;
    }

   private:
    TimeTable g_;
    double density_;
  };
  auto points = select_points(n.optional("region"), t);
  TimeTable g = read_vector_value(n.required("acceleration"), t.body.dimension);
  return std::unique_ptr<Condition>(new Gravity(std::move(points), std::move(g), t.body.density));
});

// `pressure`: a pressure p(t) (constant or tabulated over time; N/m^2 in 3D, N/m in 2D) on a
// layer of points one spacing thick, as the pulse's body force b_ext = p(t)/dx n.
const bool pressure_registered = register_condition("pressure", [](const CaseNode& n,
                                                                   const ConditionTarget& t) {
  class Pressure : public Condition {
   public:
    Pressure(std::vector<std::uint32_t> p, TimeTable pressure, Vec3 direction, double spacing)
        : pressure_(std::move(pressure)), direction_(direction.normalized()), spacing_(spacing) {
      points_ = std::move(p);
    }
    void add_external_force(Body& body, double time) const override {
      const Vec3 b = (pressure_.value(time).x() / spacing_) * direction_;
      for (std::uint32_t i : points_) body.external_force_density[i] += b;
    }

   private:
    TimeTable pressure_;
    Vec3 direction_;
    double spacing_;
  };
  auto points = select_points(n.optional("region"), t);
  TimeTable p = read_scalar_value(n.required("value"));
  const CaseNode dn = n.required("direction");
  const Vec3 direction = dn.as_vector(t.body.dimension);
  if (direction.norm() == 0) dn.fail("a non-zero direction");
  return std::unique_ptr<Condition>(
      new Pressure(std::move(points), std::move(p), direction, t.spacing));
});

}  // namespace

}  // namespace ckpd
