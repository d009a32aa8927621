#include "bodies/linear_operator.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "bodies/ckpd_model.hpp"
#include "bodies/family_scratch.hpp"
#include "bodies/force_model.hpp"
#include "bodies/pmb_model.hpp"

namespace ckpd {

namespace {

// Where column c sits in row r: 0 for r itself, else 1 + c's place in r's family row.
std::size_t column_slot(const Body& body, std::size_t r, std::uint32_t c) {
  if (c == r) return 0;
  const auto begin =
      body.family.neighbour.begin() + static_cast<std::ptrdiff_t>(body.family.offset[r]);
  const auto end =
      body.family.neighbour.begin() + static_cast<std::ptrdiff_t>(body.family.offset[r + 1]);
  const auto it = std::lower_bound(begin, end, c);
  if (it == end || *it != c)
    throw std::logic_error("linear operator: a set's vertices are not in each other's families");
  return 1 + static_cast<std::size_t>(it - begin);
}

// Adds scale * lin.block(v, w) for every vertex pair of one set to the rows `rows` lists
// (vertex v is point vertex[v]); with `only_centre`, to vertex 0's row alone.
template <int kVertices>
void add_set(const Body& body, LinearOperator& op, const SetLinearisation<kVertices>& lin,
             const std::uint32_t (&vertex)[kVertices], const double (&scale)[kVertices],
             bool only_centre) {
  for (int v = 0; v < (only_centre ? 1 : kVertices); ++v) {
    const std::size_t row = vertex[v];
    Eigen::Matrix3d* blocks = &op.block[op.offset[row]];
    for (int w = 0; w < kVertices; ++w)
      blocks[column_slot(body, row, vertex[w])] += scale[v] * lin.block(v, w);
  }
}

template <class Model>
void assemble(const Model& model, const Body& body, LinearOperator& op) {
  const std::size_t n = body.size();
  const bool pairs = Model::kTriangles && model.has_triangles();
  const bool triples = Model::kTetrahedra && model.has_tetrahedra();
  const bool energy_consistent = body.force_form == ForceForm::energy_consistent;
  const double degenerate = body.degenerate_fraction;
  const std::vector<double>& V = body.volume;
  FamilyScratch s;
  for (std::size_t c = 0; c < n; ++c) {
    s.load(body, c, body.damage_enabled, pairs || triples);
    const std::uint32_t centre = static_cast<std::uint32_t>(c);
    // The centre's force weight per set of each order; under energy_consistent vertex d's
    // share is V^c w / ((n + 1) V^d), under own_family only the centre's row takes w.
    auto scales = [&](double w, int vertices, const std::uint32_t* vertex, double* scale) {
      for (int v = 0; v < vertices; ++v)
        scale[v] = energy_consistent ? V[c] * w / (vertices * V[vertex[v]]) : w;
    };
    const double w1 = body.dv1[c];
    for (std::size_t a = 0; a < s.size(); ++a) {
      const std::uint32_t vertex[2] = {centre, s.index[a]};
      double scale[2];
      scales(w1, 2, vertex, scale);
      add_set<2>(body, op, model.bond_linearisation(s.ref[a]), vertex, scale, !energy_consistent);
    }
    if constexpr (Model::kTriangles) {
      if (pairs) {
        const double w2 = model.triangle_force_weight(body.dv2[c]);
        s.for_each_pair([&](std::size_t a, std::size_t e) {
          if (model.triangle_term(s.ref[a], s.ref[e], s.ref[a], s.ref[e], degenerate).degenerate)
            return;
          const std::uint32_t vertex[3] = {centre, s.index[a], s.index[e]};
          double scale[3];
          scales(w2, 3, vertex, scale);
          add_set<3>(body, op, model.triangle_linearisation(s.ref[a], s.ref[e]), vertex, scale,
                     !energy_consistent);
        });
      }
    }
    if constexpr (Model::kTetrahedra) {
      if (triples) {
        const double w3 = model.tetrahedron_force_weight(body.dv3[c]);
        s.for_each_triple([&](std::size_t a, std::size_t e, std::size_t f) {
          if (model
                  .tetrahedron_term(s.ref[a], s.ref[e], s.ref[f], s.ref[a], s.ref[e], s.ref[f],
                                    degenerate)
                  .degenerate)
            return;
          const std::uint32_t vertex[4] = {centre, s.index[a], s.index[e], s.index[f]};
          double scale[4];
          scales(w3, 4, vertex, scale);
          add_set<4>(body, op, model.tetrahedron_linearisation(s.ref[a], s.ref[e], s.ref[f]),
                     vertex, scale, !energy_consistent);
        });
      }
    }
  }
}

}  // namespace

LinearOperator reference_linear_operator(const Body& body) {
  const std::size_t n = body.size();
  LinearOperator op;
  op.offset.resize(n + 1);
  op.offset[0] = 0;
  for (std::size_t i = 0; i < n; ++i)
    op.offset[i + 1] = op.offset[i] + 1 + body.family.family_size(i);
  op.block.assign(op.offset[n], Eigen::Matrix3d::Zero());
  const ForceModelKernels& kernels = force_model(body);
  if (&kernels == &ckpd_kernels() || &kernels == &ckpd_seth_hill_kernels() ||
      &kernels == &ckpd_conservative_kernels() ||
      &kernels == &ckpd_seth_hill_conservative_kernels()) {
    // The linearisation does not depend on the strain measure (e_m'(1) = 1 for every m).
    assemble(CkpdModel::of(body), body, op);
  } else if (std::string(kernels.name) == PmbModel::kName) {
    assemble(PmbModel::of(body), body, op);
  } else {
    throw std::invalid_argument(std::string("the '") + kernels.name +
                                "' model has no linearisation at the reference state (the far "
                                "field needs the ckpd or pmb model)");
  }
  return op;
}

void apply_linear_operator(const LinearOperator& op, const Body& body, std::vector<Vec3>& b) {
  const std::size_t n = body.size();
  b.resize(n);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Matrix3d* row = &op.block[op.offset[i]];
    Vec3 sum = row[0] * body.displacement[i];
    std::size_t slot = 1;
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k, ++slot)
      sum += row[slot] * body.displacement[body.family.neighbour[k]];
    b[i] = sum;
  }
}

}  // namespace ckpd
