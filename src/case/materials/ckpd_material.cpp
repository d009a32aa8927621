// `model: ckpd` (the default): E and nu give C1, C2, C3 (MODEL.md section 3) or, with
// `constants: calibrated` on the body, the lattice's calibrated constants (bodies/patch_test.hpp);
// the critical stretch is given or follows from the fracture energy (MODEL.md section 4);
// `strain_measure: {m: M}` (default m = 1/2, e = l/L - 1) selects the Seth-Hill strain measure
// of every family (bodies/ckpd_model.hpp).
#include <cmath>
#include <optional>
#include <sstream>

#include "bodies/material.hpp"
#include "bodies/patch_test.hpp"
#include "src/case/material_model.hpp"

namespace ckpd {

namespace {

class CkpdMaterial : public MaterialModel {
 public:
  explicit CkpdMaterial(const CaseNode& m) {
    density_ = m.required("density").as_in_range(kMinDensity, kMaxDensity,
                                                 "a density in kg/m^3 (kg/m^2 in 2D)");
    youngs_modulus_ = m.required("youngs_modulus")
                          .as_in_range(kMinModulus, kMaxModulus, "a Young's modulus in Pa");
    const CaseNode nu = m.required("poisson_ratio");
    poisson_ratio_ = nu.as_double();
    if (!(poisson_ratio_ > -1 && poisson_ratio_ < 0.5)) nu.fail("a Poisson's ratio in (-1, 0.5)");
    if (auto g = m.optional("fracture_energy")) fracture_energy_ = g->as_positive();
    if (auto s = m.optional("critical_stretch")) critical_stretch_ = s->as_positive();
    refuse_keys_of(m, "ckpd", "state_based", {"lambda_bar", "mu_bar"});
    if (fracture_energy_ && critical_stretch_)
      m.fail("either fracture_energy or critical_stretch, not both");
    strain_measure_ = strain_measure_of(m);
    if (auto sm = m.optional("strain_measure")) strain_measure_node_ = sm->required("m");
  }

  std::optional<ElasticConstants> elastic() const override {
    return ElasticConstants{youngs_modulus_, poisson_ratio_};
  }

  void define(BodyDefinition& def, const MaterialTarget& t) const override {
    def.model = nullptr;  // CKPD
    def.strain_measure = strain_measure_;
    def.constants =
        interaction_constants(t.dimension, youngs_modulus_, poisson_ratio_, t.plane, t.horizon);
    if (t.calibrated)
      def.constants = calibrated_constants(t.dimension, youngs_modulus_, poisson_ratio_, t.plane,
                                           t.horizon, t.spacing);
    refuse_anti_barrier(def.constants, t);
    if (critical_stretch_) {
      def.critical_stretch = *critical_stretch_;
    } else if (fracture_energy_) {
      def.critical_stretch = critical_stretch_from_fracture_energy(
          t.dimension, youngs_modulus_, poisson_ratio_, t.plane, t.horizon, *fracture_energy_);
    }
  }

 private:
  // For m <= 0 a set's energy C R e_m^2 / 2 goes to +infinity as it collapses when C > 0 (the
  // barrier), but to -infinity when C < 0: a set with a negative constant would then release
  // unbounded energy by collapsing, and nothing bounds the body's energy from below. Refused
  // (THEORY.md section 2, "Strain measures"): 3D and plane strain need nu >= 1/4, plane stress
  // nu >= 1/3 (lambda >= mu), or constants that are not negative.
  void refuse_anti_barrier(const InteractionConstants& c, const MaterialTarget& t) const {
    if (strain_measure_ > 0 || !strain_measure_node_) return;
    const bool triangles = c.c2 < 0, tetrahedra = c.c3 < 0;
    if (!triangles && !tetrahedra) return;
    std::ostringstream msg;
    msg << "m > 0 for this material (m = " << strain_measure_ << " makes the energy of its "
        << (triangles ? "triangles (C2 = " : "tetrahedra (C3 = ") << (triangles ? c.c2 : c.c3)
        << " < 0" << (t.calibrated ? ", calibrated" : "") << ") go to minus infinity as they "
        << "collapse: no barrier but a pull towards collapse; the Seth-Hill measures with m <= 0 "
        << "need C2, C3 >= 0, i.e. nu >= "
        << (t.dimension == 2 && t.plane != PlaneMode::strain ? "1/3 in plane stress" : "1/4")
        << ")";
    strain_measure_node_->fail(msg.str());
  }

  double youngs_modulus_ = 0, poisson_ratio_ = 0;
  std::optional<CaseNode> strain_measure_node_;  // where m was given (errors name it)
  double strain_measure_ = 0.5;
  std::optional<double> fracture_energy_, critical_stretch_;
};

const bool keys_registered = register_key_variant(
    "material",
    {"ckpd",
     "the CKPD model: bonds, triangles and tetrahedra with constants from E and nu",
     {{"youngs_modulus",
       ValueKind::number,
       "Pa",
       kRequired,
       "Young's modulus E",
       {},
       "1e-3 to 1e16"},
      {"poisson_ratio", ValueKind::number, "-", kRequired, "Poisson's ratio nu", {}, "(-1, 0.5)"},
      fracture_energy_key("none (give it or critical_stretch for failure)"),
      {"critical_stretch",
       ValueKind::number,
       "-",
       "from fracture_energy; none: no failure",
       "the bond stretch at which a bond fails",
       {},
       "> 0"},
      strain_measure_key()}});

const bool registered = register_material_model(
    "ckpd", [](const CaseNode& m) { return std::make_unique<CkpdMaterial>(m); });

}  // namespace

}  // namespace ckpd
