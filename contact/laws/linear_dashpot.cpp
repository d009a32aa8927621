#include "contact/laws/linear_dashpot.hpp"

#include <limits>

#include "contact/dem_law.hpp"

namespace ckpd {
namespace {

class LinearDashpot final : public DemLaw {
 public:
  LinearDashpot(double coefficient, double restitution, double mu, double ratio)
      : coefficient_(coefficient),
        zeta_(linear_dashpot::damping_ratio(restitution)),
        ratio_(ratio) {
    friction = mu;
  }
  NormalResponse normal(double overlap, const LawPoint& a, const LawPoint& b,
                        bool wall) const override {
    const double k = coefficient_ * a.volume * (wall ? a.volume : b.volume);
    const double m = effective_mass(a, b, wall);
    NormalResponse r;
    r.force = k * overlap;
    r.stiffness = k;
    r.energy = 0.5 * k * overlap * overlap;
    r.damping = 2 * zeta_ * std::sqrt(k * m);
    r.tangential_stiffness = ratio_ * k;
    return r;
  }
  double damping_ratio() const override { return zeta_; }

 private:
  double coefficient_, zeta_, ratio_;
};

const bool registered = register_law(
    "linear_dashpot",
    {"linear spring k = c V^i V^j with a dashpot from e, linear tangential spring, Coulomb "
     "friction",
     {restitution_parameter(),
      friction_parameter(),
      {"tangential_stiffness_ratio", "k_t / k_n > 0 (default 2/7)", false, 1, valid_positive}},
     true,
     [](const LawInputs& in) -> std::shared_ptr<const DemLaw> {
       return std::make_shared<LinearDashpot>(in.coefficient, side_value(in, "restitution", 0),
                                              value_or(in, "friction", 0),
                                              value_or(in, "tangential_stiffness_ratio", 2.0 / 7));
     }});

}  // namespace
}  // namespace ckpd
