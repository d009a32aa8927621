#pragma once
// The serial, set-by-set assembly of the reference-state linear operator (the engine's before
// it was parallel): every set's blocks added straight into the global rows, centre by centre.
// The parallel assembly (bodies/linear_operator.hpp) sums each centre's sets first, so it
// equals this one to round-off only; tests/test_linear_operator.cpp compares the two. Header
// only (a template over the force model); linked by the tests.
#include "bodies/linear_operator.hpp"

namespace ckpd {

namespace linear_operator_detail {
// Adds scale * lin.block(v, w) for every vertex pair of one set to the rows `rows` lists
// (vertex v is point vertex[v], at slot slot[v] of the centre's column table); with
// `only_centre`, to vertex 0's row alone.
template <int kVertices>
inline void add_set(LinearOperator& op, const SetLinearisation<kVertices>& lin,
                    const std::uint32_t (&vertex)[kVertices], const std::size_t (&slot)[kVertices],
                    const std::vector<std::size_t>& table, std::size_t m,
                    const double (&scale)[kVertices], bool only_centre) {
  for (int v = 0; v < (only_centre ? 1 : kVertices); ++v) {
    const std::size_t row = vertex[v];
    Eigen::Matrix3d* blocks = &op.block[op.row[row]];
    for (int w = 0; w < kVertices; ++w) {
      const std::size_t column = table[slot[v] * m + slot[w]];
      if (column == kNoColumn)
        throw std::logic_error(
            "linear operator: a set's vertices are not in each other's families");
      blocks[column] += scale[v] * lin.block(v, w);
    }
  }
}
}  // namespace linear_operator_detail

// op: the rows' zeroed blocks, as reference_linear_operator allocates them.
template <class Model>
void assemble_linear_operator_serial_of(const Model& model, const Body& body, LinearOperator& op) {
  const bool sets = (Model::kTriangles && model.has_triangles()) ||
                    (Model::kTetrahedra && model.has_tetrahedra());
  const bool only_centre = body.force_form != ForceForm::energy_consistent;
  FamilyScratch s;
  std::vector<std::size_t> table;
  for (std::size_t c = 0; c < body.size(); ++c) {
    s.load(body, c, body.damage_enabled, sets);
    linear_operator_detail::column_table(body, static_cast<std::uint32_t>(c), s, table);
    const std::size_t m = s.size() + 1;
    linear_operator_detail::for_each_set(
        model, body, c, s,
        [&](const auto& lin, const auto& vertex, const auto& slot, const auto& scale) {
          linear_operator_detail::add_set(op, lin, vertex, slot, table, m, scale, only_centre);
        });
  }
}

}  // namespace ckpd
