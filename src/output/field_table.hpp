#pragma once
// The per-point fields a run can write into its frames, as one table: a field is one row (its
// name, number of components, number type and how its values are taken from the simulation).
// The frame writer, the case loader's check of `output.fields` and the XDMF all read this
// table, so adding a field touches nothing else.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "src/engine/simulation.hpp"

namespace ckpd {

enum class FieldNumber { float64, int32 };

// The body a field is taken from: a body of the case (its index `index`), or a rank's part of
// one, whose points are points `whole_index[i]` of the whole body `whole` (as built: for what is
// fixed in the reference configuration over the whole body; null: `body` is whole).
struct FieldSource {
  const Body& body;
  std::size_t index = 0;
  const std::vector<std::uint32_t>* whole_index = nullptr;
  const Body* whole = nullptr;
};

struct FieldSpec {
  std::string name;
  // 1: scalar; 3: vector (x, y, z); 6: symmetric tensor in XDMF's Tensor6 order (xx, xy, xz,
  // yy, yz, zz); 9: tensor, row-major.
  int components = 1;
  FieldNumber number = FieldNumber::float64;
  bool needs_energy = false;  // filled only by an evaluation with energy (frame steps get one)
  std::string description;
  // Fills `out` with body.size() x components values of the source's body.
  std::function<void(const FieldSource& source, std::vector<double>& out)> extract;
};

const std::vector<FieldSpec>& field_table();
// Null for a name that is not in the table.
const FieldSpec* find_field(const std::string& name);
// The table's names, in table order.
const std::vector<std::string>& known_field_names();
// "position, reference_position, ..." for error messages.
std::string known_field_list();
// XDMF's AttributeType for a number of components.
const char* xdmf_attribute_type(int components);

}  // namespace ckpd
