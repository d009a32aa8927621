#pragma once
// Materials of deformable bodies, by force model (`model: ckpd | pmb` on a material, default
// ckpd). Each model's material is one small class in src/case/materials/, registered by name
// from its own file (like a condition type or a LAMMPS pair style): it reads its own keys and
// gives a body its force model (bodies/force_model.hpp), constants and critical stretch.
#include <functional>
#include <initializer_list>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "bodies/body.hpp"
#include "contact/dem_law.hpp"
#include "src/input/case_node.hpp"
#include "src/input/key_table.hpp"

namespace ckpd {

// Physical bounds of material inputs (SI). Diamond's modulus is 1.2e12 Pa, osmium's density
// 2.26e4 kg/m^3. Wider values are typos or probes, and they overflow or underflow the stable
// step (E = 1e300 gave an unbounded step).
constexpr double kMinModulus = 1e-3, kMaxModulus = 1e16;
constexpr double kMinDensity = 1e-9, kMaxDensity = 1e9;

// What a material needs to know about the body it is given to.
struct MaterialTarget {
  int dimension = 3;
  PlaneMode plane = PlaneMode::none;
  double horizon = 0;
  double spacing = 0;
  bool calibrated = false;  // the body asks for `constants: calibrated`
};

class MaterialModel {
 public:
  virtual ~MaterialModel() = default;
  double density() const { return density_; }
  // Young's modulus and Poisson's ratio, when the model has them (contact laws use them).
  virtual std::optional<ElasticConstants> elastic() const { return std::nullopt; }
  // Sets def.model, def.constants and def.critical_stretch for a body. Throws
  // std::invalid_argument (with the reason) when the material cannot serve that body.
  virtual void define(BodyDefinition& def, const MaterialTarget& target) const = 0;

 protected:
  double density_ = 0;
};

// A key of another model on this one is refused with a message naming the model it belongs to
// (file, line and key, like any bad input).
inline void refuse_keys_of(const CaseNode& m, const std::string& mine, const std::string& theirs,
                           std::initializer_list<const char*> keys) {
  for (const char* k : keys)
    if (auto n = m.optional(k))
      n->fail(std::string("no ") + k + " on a " + mine + " material (a key of model: " + theirs +
              ")");
}

// The Seth-Hill exponent of `strain_measure: {m: M}` if the material has the key, else
// `fallback` (1/2: l/L - 1). Shared by the models that take a strain measure.
// A Seth-Hill exponent m is refused outside [-kMaxStrainMeasure, kMaxStrainMeasure].
constexpr double kMaxStrainMeasure = 2;
double strain_measure_of(const CaseNode& m, double fallback = 0.5);

// Keys several models share, for their key-table variants (src/input/key_table.hpp).
KeySpec strain_measure_key();
KeySpec fracture_energy_key(const std::string& fallback);

// Reads a material's own keys (not `model`); the caller rejects any key left unread.
using MaterialFactory = std::function<std::unique_ptr<MaterialModel>(const CaseNode&)>;
std::map<std::string, MaterialFactory>& material_registry();
bool register_material_model(const std::string& model, MaterialFactory factory);

// The material described by `node` (its `model`, default ckpd, and that model's keys). Unknown
// models (the known ones are listed) and unknown keys are errors naming file, line and key.
std::unique_ptr<MaterialModel> make_material(const CaseNode& node);

}  // namespace ckpd
