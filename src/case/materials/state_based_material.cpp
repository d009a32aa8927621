// `model: state_based`: the nonlinear ordinary state-based solid of seed 002
// (bodies/state_based_model.hpp). Keys: density; either lambda_bar and mu_bar (the model's own
// moduli, Pa; N/m in 2D) or youngs_modulus and poisson_ratio (matched at small strain:
// lambda_bar = lambda - mu, mu_bar = 2 mu in 2D, 5 mu / 2 in 3D, with the body's plane mode);
// strain_measure: {m: M} (default 1/2); for brittle failure, fracture_energy (Gc, J/m^2; J/m
// in 2D). The CKPD model's keys (critical_stretch, constants: calibrated) are errors.
#include <cmath>
#include <optional>

#include "bodies/material.hpp"
#include "bodies/state_based_model.hpp"
#include "src/case/material_model.hpp"

namespace ckpd {

namespace {

class StateBasedMaterial : public MaterialModel {
 public:
  explicit StateBasedMaterial(const CaseNode& m) {
    density_ = m.required("density").as_in_range(kMinDensity, kMaxDensity,
                                                 "a density in kg/m^3 (kg/m^2 in 2D)");
    if (auto s = m.optional("critical_stretch"))
      s->fail(
          "no critical_stretch on a state_based material (a CKPD/PMB key): its bonds fail by "
          "their energy; give fracture_energy (Gc, J/m^2) for failure");
    const bool moduli = m.has("lambda_bar") || m.has("mu_bar");
    const bool engineering = m.has("youngs_modulus") || m.has("poisson_ratio");
    if (moduli && engineering)
      m.fail("either lambda_bar and mu_bar or youngs_modulus and poisson_ratio, not both");
    if (engineering) {
      youngs_modulus_ = m.required("youngs_modulus")
                            .as_in_range(kMinModulus, kMaxModulus, "a Young's modulus in Pa");
      const CaseNode nu = m.required("poisson_ratio");
      poisson_ratio_ = nu.as_double();
      if (!(poisson_ratio_ > -1 && poisson_ratio_ < 0.5)) nu.fail("a Poisson's ratio in (-1, 0.5)");
    } else {
      const CaseNode mu = m.required("mu_bar");
      mu_bar_ = mu.as_in_range(kMinModulus, kMaxModulus, "mu_bar in Pa (> 0)");
      const CaseNode lambda = m.required("lambda_bar");
      lambda_bar_ = lambda.as_in_range(-kMaxModulus, kMaxModulus, "lambda_bar in Pa");
      lambda_node_ = lambda;
    }
    if (auto g = m.optional("fracture_energy")) fracture_energy_ = g->as_positive();
    strain_measure_ = strain_measure_of(m);
  }

  // E and nu for contact laws (hertz_mindlin) when the material gives them; lambda_bar and
  // mu_bar alone do not fix E and nu without the body's dimension, so Hertz then asks the
  // contact section for them.
  std::optional<ElasticConstants> elastic() const override {
    if (youngs_modulus_ > 0) return ElasticConstants{youngs_modulus_, poisson_ratio_};
    return std::nullopt;
  }

  void define(BodyDefinition& def, const MaterialTarget& t) const override {
    if (t.calibrated)
      throw std::invalid_argument(
          "calibrated constants are a CKPD option; a state_based material has lambda_bar and "
          "mu_bar (or E and nu)");
    StateBasedConstants k;
    if (youngs_modulus_ > 0) {
      const ElasticModuli e = elastic_moduli(t.dimension, youngs_modulus_, poisson_ratio_, t.plane);
      k = state_based_constants(t.dimension, e.lambda, e.mu);
    } else {
      k.lambda_bar = lambda_bar_;
      k.mu_bar = mu_bar_;
      // Bulk response lambda_bar d^2 / 2 + mu_bar d > 0 (THEORY.md): otherwise no stable solid.
      if (!(lambda_bar_ * t.dimension / 2 + mu_bar_ > 0))
        lambda_node_->fail("lambda_bar > -2 mu_bar / d (a positive bulk response)");
    }
    k.m = strain_measure_;
    if (fracture_energy_)
      k.failure_beta = state_based_failure_beta(t.dimension, t.horizon, *fracture_energy_);
    def.model = &state_based_kernels();
    def.constants = InteractionConstants{0, 0, 0};
    def.state_based = k;
  }

 private:
  double youngs_modulus_ = 0, poisson_ratio_ = 0;
  double lambda_bar_ = 0, mu_bar_ = 0;
  std::optional<CaseNode> lambda_node_;
  double strain_measure_ = 0.5;
  std::optional<double> fracture_energy_;
};

const bool keys_registered = register_key_variant(
    "material", {"state_based",
                 "the nonlinear ordinary state-based solid: lambda_bar and mu_bar, or E and nu",
                 {{"youngs_modulus",
                   ValueKind::number,
                   "Pa",
                   "give it and poisson_ratio, or the moduli",
                   "Young's modulus E (matched at small strain)",
                   {},
                   "1e-3 to 1e16"},
                  {"poisson_ratio",
                   ValueKind::number,
                   "-",
                   "give it and youngs_modulus, or the moduli",
                   "Poisson's ratio nu",
                   {},
                   "(-1, 0.5)"},
                  {"lambda_bar",
                   ValueKind::number,
                   "Pa (N/m in 2D)",
                   "give it and mu_bar, or E and nu",
                   "the model's first modulus",
                   {},
                   "> -2 mu_bar / dimension"},
                  {"mu_bar",
                   ValueKind::number,
                   "Pa (N/m in 2D)",
                   "give it and lambda_bar, or E and nu",
                   "the model's second modulus",
                   {},
                   "> 0"},
                  fracture_energy_key("none (no failure)"),
                  strain_measure_key()}});

const bool registered = register_material_model(
    "state_based", [](const CaseNode& m) { return std::make_unique<StateBasedMaterial>(m); });

}  // namespace

}  // namespace ckpd
