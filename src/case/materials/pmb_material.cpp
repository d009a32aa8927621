// `model: pmb`: the PMB bond model (bodies/pmb_model.hpp). Keys: density, micromodulus (c, N/m^6
// in 3D, N/m^5 in 2D) and, for failure, critical_stretch (s0). The model's kernels are
// instantiated here, once.
#include <cmath>
#include <optional>

#include "bodies/force_model_kernels.hpp"
#include "bodies/pmb_model.hpp"
#include "src/case/material_model.hpp"

namespace ckpd {

namespace {

class PmbMaterial : public MaterialModel {
 public:
  explicit PmbMaterial(const CaseNode& m) {
    density_ = m.required("density").as_in_range(kMinDensity, kMaxDensity,
                                                 "a density in kg/m^3 (kg/m^2 in 2D)");
    micromodulus_ = m.required("micromodulus").as_positive();
    if (!std::isfinite(micromodulus_) || micromodulus_ > 1e40)
      m.required("micromodulus").fail("a micromodulus in N/m^6 of at most 1e40");
    if (auto s = m.optional("critical_stretch")) critical_stretch_ = s->as_positive();
    refuse_keys_of(m, "pmb", "state_based", {"lambda_bar", "mu_bar"});
  }

  void define(BodyDefinition& def, const MaterialTarget& t) const override {
    if (t.calibrated)
      throw std::invalid_argument(
          "calibrated constants are a CKPD option; a pmb material has "
          "its micromodulus");
    def.model = &kernels_of<PmbModel>();
    def.constants = InteractionConstants{micromodulus_, 0, 0};
    if (critical_stretch_) def.critical_stretch = *critical_stretch_;
  }

 private:
  double micromodulus_ = 0;
  std::optional<double> critical_stretch_;
};

const bool keys_registered =
    register_key_variant("material", {"pmb",
                                      "the prototype microelastic brittle bond model",
                                      {{"micromodulus",
                                        ValueKind::number,
                                        "N/m^6 (N/m^5 in 2D)",
                                        kRequired,
                                        "the micromodulus c",
                                        {},
                                        "> 0, at most 1e40"},
                                       {"critical_stretch",
                                        ValueKind::number,
                                        "-",
                                        "none (no failure)",
                                        "the bond stretch s0 at which a bond fails",
                                        {},
                                        "> 0"}}});

const bool registered = register_material_model(
    "pmb", [](const CaseNode& m) { return std::make_unique<PmbMaterial>(m); });

}  // namespace

}  // namespace ckpd
