#include "src/case/material_model.hpp"

#include <cmath>

namespace ckpd {

namespace {

// The keys every material takes (each model adds its own: src/case/materials/) and the strain
// measure's, in the key table (src/input/key_table.hpp).
const bool material_keys_registered = register_key_section([] {
  KeySection s{"material",
               "materials entries",
               "A material, under its name in `materials`. Its `model` (the force model) picks its "
               "keys.",
               {{"model", ValueKind::text, "-", "ckpd", "the force model"},
                {"density",
                 ValueKind::number,
                 "kg/m^3 (kg/m^2 in 2D)",
                 kRequired,
                 "the mass density",
                 {},
                 "1e-9 to 1e9"}}};
  s.discriminator = "model";
  s.default_variant = "ckpd";
  return s;
}());

const bool strain_measure_keys_registered = register_key_section(
    {"strain_measure",
     "strain_measure",
     "The Seth-Hill strain measure e_m = (r^(2m) - 1) / (2m) of every bond, triangle and "
     "tetrahedron's stretch ratio r (m = 0: log r).",
     {{"m", ValueKind::number, "-", kRequired,
       "the exponent m: 0.5 is r - 1 (the measure without this key), 0 is log r"}}});

}  // namespace

KeySpec strain_measure_key() {
  return {"strain_measure",
          ValueKind::section,
          "-",
          "m = 0.5 (r - 1)",
          "the strain measure of every family",
          {},
          "",
          "strain_measure"};
}

KeySpec fracture_energy_key(const std::string& fallback) {
  return {"fracture_energy",
          ValueKind::number,
          "J/m^2 (J/m in 2D)",
          fallback,
          "the fracture energy Gc, from which bonds fail",
          {},
          "> 0"};
}

double strain_measure_of(const CaseNode& m, double fallback) {
  auto sm = m.optional("strain_measure");
  if (!sm) return fallback;
  if (!sm->is_map()) sm->fail("a map {m: M} (the Seth-Hill exponent, e.g. {m: 0})");
  const CaseNode exponent = sm->required("m");
  // The named measures lie in [-1, 1] (Almansi, log, Biot, Green). A stiffness growing as
  // r^(4m - 2) makes any larger |m| overflow at strains a run meets: m = 1e6 gave null energies.
  const double value = exponent.as_double();
  if (!(std::abs(value) <= kMaxStrainMeasure))
    exponent.fail("a Seth-Hill exponent m from -2 to 2 (0.5 is l/L - 1, 0 is log, 1 Green's)");
  sm->finish();
  return value;
}

std::map<std::string, MaterialFactory>& material_registry() {
  static std::map<std::string, MaterialFactory> registry;
  return registry;
}

bool register_material_model(const std::string& model, MaterialFactory factory) {
  material_registry()[model] = std::move(factory);
  return true;
}

std::unique_ptr<MaterialModel> make_material(const CaseNode& node) {
  const auto& registry = material_registry();
  std::string model = "ckpd";
  const std::optional<CaseNode> model_node = node.optional("model");
  if (model_node) model = model_node->as_string();
  const auto it = registry.find(model);
  if (it == registry.end()) {
    std::string known;
    for (const auto& [name, f] : registry) known += (known.empty() ? "" : ", ") + name;
    model_node->fail("a force model (" + known + ")");
  }
  std::unique_ptr<MaterialModel> m = it->second(node);
  node.finish();
  return m;
}

}  // namespace ckpd
