// `initial_velocity`: v = value + angular_velocity x (X - center) on a region (or the whole
// body) at t = 0. The motion is then free.
#include "src/engine/condition.hpp"

namespace ckpd {

namespace {

class InitialVelocity : public Condition {
 public:
  InitialVelocity(std::vector<std::uint32_t> points, Vec3 value, Vec3 omega, Vec3 centre)
      : value_(value), omega_(omega), centre_(centre) {
    points_ = std::move(points);
  }
  void initialise(Body& body) const override {
    for (std::uint32_t i : points_)
      body.velocity[i] = value_ + omega_.cross(body.reference_position[i] - centre_);
  }
  double max_speed() const override { return speed_; }
  double speed_ = 0;

 private:
  Vec3 value_, omega_, centre_;
};

const bool registered =
    register_condition("initial_velocity", [](const CaseNode& n, const ConditionTarget& t) {
      const int dim = t.body.dimension;
      auto points = select_points(n.optional("region"), t);
      Vec3 value = Vec3::Zero(), omega = Vec3::Zero(), centre = Vec3::Zero();
      if (auto v = n.optional("value"))
        value = v->as_vector_below(dim, CaseNode::kMaxSpeed, "a velocity in m/s");
      if (auto w = n.optional("angular_velocity")) {
        // In 2D the angular velocity is a scalar about z.
        omega = dim == 3 ? w->as_vector(3) : Vec3(0, 0, w->as_double());
        centre = n.required("center").as_vector(dim);
      }
      auto c = std::make_unique<InitialVelocity>(points, value, omega, centre);
      for (std::uint32_t i : points)
        c->speed_ = std::max(c->speed_,
                             (value + omega.cross(t.body.reference_position[i] - centre)).norm());
      return std::unique_ptr<Condition>(std::move(c));
    });

}  // namespace

}  // namespace ckpd
