#include "contact/laws/hertz_mindlin.hpp"

#include <numbers>
#include <stdexcept>
#include <string>

#include "contact/dem_law.hpp"

namespace ckpd {
namespace {

class HertzMindlin final : public DemLaw {
 public:
  HertzMindlin(double modulus, double shear, double pair_radius, double wall_radius, double e,
               double mu)
      : modulus_(modulus), shear_(shear), pair_radius_(pair_radius), wall_radius_(wall_radius) {
    const double l = std::log(e);
    zeta_ = std::sqrt(5.0 / 6) * -l / std::sqrt(l * l + std::numbers::pi * std::numbers::pi);
    friction = mu;
  }
  NormalResponse normal(double overlap, const LawPoint& a, const LawPoint& b,
                        bool wall) const override {
    const double radius = wall ? wall_radius_ : pair_radius_;
    const double m = effective_mass(a, b, wall);
    const double root = std::sqrt(radius * overlap);
    NormalResponse r;
    r.force = 4.0 / 3 * modulus_ * root * overlap;
    r.stiffness = 2 * modulus_ * root;
    r.energy = 0.4 * r.force * overlap;
    r.damping = 2 * zeta_ * std::sqrt(r.stiffness * m);
    r.tangential_stiffness = 8 * shear_ * root;
    return r;
  }
  double damping_ratio() const override { return zeta_; }

 private:
  double modulus_, shear_, pair_radius_, wall_radius_, zeta_ = 0;
};

// E or nu of one side: the contact section's value when it gives one (an explicit override, for
// both sides or per side), else the side's body's own (its material's, or a rigid body's or
// mesh wall's `rigid: {youngs_modulus, poisson_ratio}`).
double elastic_value(const LawInputs& in, const std::string& key, std::size_t side) {
  if (in.parameters.count(key)) return side_value(in, key, side);
  const LawInputs::Side& s = in.side[side];
  if (!s.elastic)
    throw std::invalid_argument(
        "contact law 'hertz_mindlin' needs Young's modulus and Poisson's ratio of body '" + s.name +
        "'" +
        (s.rigid ? std::string(", a ") + (s.wall ? "mesh wall" : "rigid body") +
                       ": give `youngs_modulus` and `poisson_ratio` in its `rigid` section (or "
                       "a material that has them)"
                 : ": its material's model has none") +
        ", or `youngs_modulus` and `poisson_ratio` for the pair in `contact`");
  return key == "youngs_modulus" ? s.elastic->youngs_modulus : s.elastic->poisson_ratio;
}

const bool registered = register_law(
    "hertz_mindlin",
    {"Hertz normal, Mindlin tangential stiffness from E and nu, damping from e, Coulomb friction",
     {restitution_parameter(),
      friction_parameter(),
      {"youngs_modulus",
       "E > 0 (Pa): one value, or one per side of the pair (overrides the bodies' own)", false, 2,
       valid_positive},
      {"poisson_ratio",
       "nu in (-1, 0.5): one value, or one per side of the pair (overrides the bodies' own)", false,
       2, valid_poisson},
      {"effective_radius",
       "R* > 0 (m; default l_c/4, l_c/1 against a wall, R_a R_b/(R_a + R_b) with DEM spheres)",
       false, 1, valid_positive}},
     false,
     [](const LawInputs& in) -> std::shared_ptr<const DemLaw> {
       const double e1 = elastic_value(in, "youngs_modulus", 0),
                    e2 = elastic_value(in, "youngs_modulus", 1);
       const double n1 = elastic_value(in, "poisson_ratio", 0),
                    n2 = elastic_value(in, "poisson_ratio", 1);
       const double given = value_or(in, "effective_radius", 0);
       // With a DEM sphere the sides' own radii: R* = r_1 r_2 / (r_1 + r_2) (a side of radius 0,
       // a point without a lattice, leaves the other's); against a wall the sphere's R = l_c.
       const double r1 = in.side_radius[0], r2 = in.side_radius[1];
       const double pair = r1 > 0 && r2 > 0 ? r1 * r2 / (r1 + r2)
                           : r1 + r2 > 0    ? r1 + r2
                                            : in.radius / 4;
       return std::make_shared<HertzMindlin>(
           hertz::effective_modulus(e1, n1, e2, n2), hertz::effective_shear_modulus(e1, n1, e2, n2),
           given > 0 ? given : pair, given > 0 ? given : in.radius,
           side_value(in, "restitution", 0), value_or(in, "friction", 0));
     }});

}  // namespace
}  // namespace ckpd
