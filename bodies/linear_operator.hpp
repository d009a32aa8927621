#pragma once
// The force law's linearisation at the reference state (issue 20, the far field's operator):
// b^i = sum_c K^ic u^c to first order in the displacements, one 3 x 3 block per point c of
// i's family and one for i itself. Each set contributes its linearisation (set_law.hpp,
// SetLinearisation: dF_c/du_d = -C/R g_c g_d^T, the measure's gradients g at the reference
// state) with the weights of the force form in force:
// - own_family (MODEL.md): row i takes the sets of i's own family with i's weights
//   dV1^i, k2^i, k3^i (the plain Jacobian; not symmetric near surfaces);
// - energy_consistent: every point c's sets give every vertex d the share V^c w^c / ((n+1) V^d)
//   (THEORY.md section 2b): the Hessian of the energy, divided by the receiving point's volume.
// Sets switched off by failed bonds (under the body's damage rule) and sets degenerate at the
// reference state contribute nothing, as in the kernels. The inversion penalty is zero at the
// reference state and every Seth-Hill measure has the same linearisation there (e_m'(1) = 1).
#include <Eigen/Core>
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <exception>
#include <stdexcept>
#include <vector>

#include "bodies/body.hpp"
#include "bodies/family_scratch.hpp"
#include "bodies/linear_operator_tetrahedra.hpp"
#include "bodies/set_law.hpp"

namespace ckpd {

struct LinearOperator {
  static constexpr std::size_t kNoRow = ~std::size_t{0};
  // Row i's blocks are block[row[i] .. row[i] + 1 + family size of i): first d b^i / d u^i, then
  // d b^i / d u^j for the members j of i's family in the order of body.family's row. Points of
  // one row class (operator_classes.hpp) share one row. kNoRow: a row the assembly skips.
  std::vector<std::size_t> row;
  std::vector<Eigen::Matrix3d> block;
  std::size_t classes = 0;    // rows stored
  std::size_t assembled = 0;  // of them assembled (the others turned, operator_classes.hpp)
  std::size_t bytes() const {
    return block.size() * sizeof(Eigen::Matrix3d) + row.size() * sizeof(std::size_t);
  }
};

// Every point's own row, assembled. Throws std::invalid_argument for a model without set
// linearisations (the state-based solid).
LinearOperator reference_linear_operator(const Body& body);
// The same operator with one row per row class (operator_classes.hpp): on a lattice body the
// points whose rows are the same up to the rounding of their positions share the row of the
// class's first point, assembled only there; on a point cloud every point is its own class and
// the result is reference_linear_operator's bit for bit.
LinearOperator linear_operator_by_class(const Body& body);

// Row i of K times the body's displacements, b^i = K^ii u^i + sum_j K^ij u^j, with
// visit(j, u^j) called for each member j in the family's order (the far field's screen reads the
// same displacements in the same pass). Summed in two partial sums over alternate members, added
// at the end: each block's product then waits on the one two members back, not on the last (one
// chain of additions bounded the pass). Every caller sums in this order: bit for bit alike.
template <class Visit>
inline Vec3 row_product(const LinearOperator& op, const Body& body, std::size_t i, Visit&& visit) {
  const Eigen::Matrix3d* own = &op.block[op.row[i]];  // K^ii, then the members' blocks
  const Eigen::Matrix3d* row = own + 1;
  const std::uint32_t* member = body.family.neighbour.data() + body.family.offset[i];
  const std::size_t count = body.family.offset[i + 1] - body.family.offset[i];
  const Vec3* u = body.displacement.data();
  Vec3 even = *own * u[i], odd = Vec3::Zero();
  std::size_t s = 0;
  for (; s + 1 < count; s += 2) {
    const std::uint32_t j = member[s], k = member[s + 1];
    visit(j, u[j]);
    visit(k, u[k]);
    even += row[s] * u[j];
    odd += row[s + 1] * u[k];
  }
  if (s < count) {
    visit(member[s], u[member[s]]);
    even += row[s] * u[member[s]];
  }
  return even + odd;
}

// b^i = sum_c K^ic u^c with the body's displacements, for every point.
void apply_linear_operator(const LinearOperator& op, const Body& body, std::vector<Vec3>& b);
// The corotated rows (far_field.hpp): b^i = R^i sum_j K^ij (R^iT dx^ij - dX^ij) for the rows with
// exact[i] == 0, R^i = rotation[i].
void apply_linear_operator_rows_corotated(const LinearOperator& op, const Body& body,
                                          const std::uint8_t* exact,
                                          const std::vector<Eigen::Matrix3d>& rotation,
                                          std::vector<Vec3>& b);
// Row i's share of the quadratic energy (1/2) u^T H u, H = -V K (rows summing to zero, and
// symmetric under energy_consistent): W^i = (1/4) sum_j d^ij . K^ij d^ij with d^ij = u^j - u^i,
// a strain energy density (J/m^3) that a rigid translation leaves at zero. Summed with the
// volumes over all points it is the quadratic energy exactly (THEORY.md section 11b).
double linear_energy_density(const LinearOperator& op, const Body& body, std::size_t i);
// Point i's corotated relative displacement towards j, R^T dx^ij - dX^ij, as
// R^T (u^j - u^i) + (R^T - I) dX^ij (Rt = R^T, Qt = R^T - I): without a rotation it is u^j - u^i
// bit for bit, not the difference of two nearly equal bond vectors.
inline Vec3 corotated_relative(const Body& body, const Eigen::Matrix3d& Rt,
                               const Eigen::Matrix3d& Qt, std::size_t i, std::size_t j) {
  return Rt * (body.displacement[j] - body.displacement[i]) +
         Qt * (body.reference_position[j] - body.reference_position[i]);
}
// The same of the corotated relative displacements d^ij = R^T dx^ij - dX^ij.
double linear_energy_density_corotated(const LinearOperator& op, const Body& body, std::size_t i,
                                       const Eigen::Matrix3d& R);

namespace linear_operator_detail {
// Where each point of one centre's family sits in each other's rows: at (1 + a) * m + (1 + b),
// m = slots + 1, the column slot of slot b's point in slot a's point's row (index 0: the centre
// itself); kNoColumn where b is not in a's family. Computed once per centre (m^2 searches of a
// sorted row) instead of once per vertex pair of every set, which made the assembly of the
// sphere-disc's operator (15,720 points at m = 4.015) take 300 s.
inline constexpr std::size_t kNoColumn = ~std::size_t{0};
inline void column_table(const Body& body, std::uint32_t centre, const FamilyScratch& s,
                         std::vector<std::size_t>& table) {
  const std::size_t m = s.size() + 1;
  table.assign(m * m, kNoColumn);
  auto point = [&](std::size_t x) { return x == 0 ? centre : s.index[x - 1]; };
  for (std::size_t a = 0; a < m; ++a) {
    const std::uint32_t r = point(a);
    const std::uint32_t* begin = body.family.neighbour.data() + body.family.offset[r];
    const std::uint32_t* end = body.family.neighbour.data() + body.family.offset[r + 1];
    for (std::size_t b = 0; b < m; ++b) {
      const std::uint32_t c = point(b);
      if (c == r) {
        table[a * m + b] = 0;
        continue;
      }
      const std::uint32_t* it = std::lower_bound(begin, end, c);
      if (it != end && *it == c) table[a * m + b] = 1 + static_cast<std::size_t>(it - begin);
    }
  }
}

// Whether centre c's sets reach a row the assembly writes: c's own, or (all_rows) a member's.
inline bool writes_assembled_row(const LinearOperator& op, const Body& body, std::size_t c,
                                 bool only_centre) {
  if (op.row[c] != LinearOperator::kNoRow) return true;
  if (only_centre) return false;
  for (std::size_t k = body.family.offset[c]; k < body.family.offset[c + 1]; ++k)
    if (op.row[body.family.neighbour[k]] != LinearOperator::kNoRow) return true;
  return false;
}

// One set's blocks scale[v] lin.block(v, w) for every vertex pair into one centre's local
// blocks (slot-indexed, local[a * m + b]: row slot a, column slot b), as a rank-one update per row:
// (-C/R scale_v g_v) g_w^T.
template <int kVertices>
inline void add_set_local(Eigen::Matrix3d* local, const SetLinearisation<kVertices>& lin,
                          const std::size_t (&slot)[kVertices],
                          const std::vector<std::size_t>& table, std::size_t m,
                          const double (&scale)[kVertices], bool only_centre) {
  const double curvature = -lin.curvature();
  for (int v = 0; v < (only_centre ? 1 : kVertices); ++v) {
    const Vec3 h = (curvature * scale[v]) * lin.gradient[static_cast<std::size_t>(v)];
    Eigen::Matrix3d* row = local + slot[v] * m;
    for (int w = 0; w < kVertices; ++w) {
      if (table[slot[v] * m + slot[w]] == kNoColumn)
        throw std::logic_error(
            "linear operator: a set's vertices are not in each other's families");
      row[slot[w]].noalias() += h * lin.gradient[static_cast<std::size_t>(w)].transpose();
    }
  }
}

// Adds -S(v, w) / row[v] to the centre's local blocks (local[v * m + w])
// for every row v (row 0 only with only_centre) and zeroes the sums. A non-zero block between
// slots that are not in each other's families is a logic error, as in add_set_local.
inline void add_volume_tetrahedra_to_local(Eigen::Matrix3d* local,
                                           const std::vector<std::size_t>& table, const double* row,
                                           bool only_centre, VolumeTetrahedronBlocks& t) {
  const std::size_t m = t.m;
  auto check = [&](std::size_t v, std::size_t w, const Eigen::Matrix3d& block) {
    if (table[v * m + w] == kNoColumn && !block.isZero(0))
      throw std::logic_error("linear operator: a set's vertices are not in each other's families");
  };
  for (std::size_t v = 0; v < (only_centre ? 1 : m); ++v) {
    const double f = -1.0 / row[v];
    Eigen::Matrix3d diagonal;
    diagonal << t.diagonal_at(0, v), t.diagonal_at(1, v), t.diagonal_at(2, v), t.diagonal_at(1, v),
        t.diagonal_at(3, v), t.diagonal_at(4, v), t.diagonal_at(2, v), t.diagonal_at(4, v),
        t.diagonal_at(5, v);
    local[v * m + v] += f * diagonal;
    for (std::size_t w = v + 1; w < m; ++w) {
      Eigen::Matrix3d block;
      for (int k = 0; k < 9; ++k) block(k / 3, k % 3) = t.upper_at(k, v, w);
      if (block.isZero(0)) continue;
      check(v, w, block);
      local[v * m + w] += f * block;
      if (!only_centre) {
        check(w, v, block);
        local[w * m + v] += (-1.0 / row[w]) * block.transpose();
      }
    }
  }
  // Zero what the centre wrote: under only_centre row 0 of each plane (its last lanes reach at
  // most kLanes past the row, into zeros), else every plane whole.
  const std::size_t rows = only_centre ? m + VolumeTetrahedronBlocks::kLanes : m * m;
  for (std::size_t k = 0; k < 9; ++k)
    std::fill_n(t.upper.begin() + static_cast<std::ptrdiff_t>(k * m * m), rows, 0.0);
  std::fill_n(t.diagonal.begin(), 6 * m, 0.0);
}

// Adds one centre's local blocks to the global rows of its points that are assembled (only the
// centre's row with `only_centre`) and zeroes them again (every block a set wrote has a column:
// add_set_local checked it).
inline void apply_local(LinearOperator& op, std::uint32_t centre, const FamilyScratch& s,
                        const std::vector<std::size_t>& table, Eigen::Matrix3d* local,
                        bool only_centre) {
  const std::size_t m = s.size() + 1;
  for (std::size_t a = 0; a < (only_centre ? 1 : m); ++a) {
    const std::size_t start = op.row[a == 0 ? centre : s.index[a - 1]];
    Eigen::Matrix3d* row = local + a * m;
    const std::size_t* columns = &table[a * m];
    for (std::size_t b = 0; b < m; ++b) {
      if (columns[b] == kNoColumn) continue;
      if (start != LinearOperator::kNoRow) op.block[start + columns[b]] += row[b];
      row[b].setZero();
    }
  }
}

// Calls visit(lin, vertex, slot, scale) for every set of centre c that the kernels evaluate
// (s holds c's family, loaded as the kernels load it), bonds first, then triangles and
// tetrahedra in the scratch's order. scale[v] is vertex v's weight: under energy_consistent
// V^c w / ((n + 1) V^d), under own_family the centre's force weight w (only its row is used).
// Without `tetrahedra`, bonds and triangles only (the caller takes the tetrahedra in the vector
// loop, linear_operator_tetrahedra.hpp).
template <class Model, class Visit>
inline void for_each_set(const Model& model, const Body& body, std::size_t c,
                         const FamilyScratch& s, Visit&& visit, bool tetrahedra = true) {
  const bool pairs = Model::kTriangles && model.has_triangles();
  const bool triples = Model::kTetrahedra && model.has_tetrahedra() && tetrahedra;
  const bool energy_consistent = body.force_form == ForceForm::energy_consistent;
  const double degenerate = body.degenerate_fraction;
  const std::vector<double>& V = body.volume;
  const std::uint32_t centre = static_cast<std::uint32_t>(c);
  auto scales = [&](double w, int vertices, const std::uint32_t* vertex, double* scale) {
    for (int v = 0; v < vertices; ++v)
      scale[v] = energy_consistent ? V[c] * w / (vertices * V[vertex[v]]) : w;
  };
  const double w1 = body.dv1[c];
  for (std::size_t a = 0; a < s.size(); ++a) {
    const std::uint32_t vertex[2] = {centre, s.index[a]};
    double scale[2];
    scales(w1, 2, vertex, scale);
    const std::size_t slot[2] = {0, 1 + a};
    visit(model.bond_linearisation(s.ref[a]), vertex, slot, scale);
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
        const std::size_t slot[3] = {0, 1 + a, 1 + e};
        visit(model.triangle_linearisation(s.ref[a], s.ref[e]), vertex, slot, scale);
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
        const std::size_t slot[4] = {0, 1 + a, 1 + e, 1 + f};
        visit(model.tetrahedron_linearisation(s.ref[a], s.ref[e], s.ref[f]), vertex, slot, scale);
      });
    }
  }
}
}  // namespace linear_operator_detail

// Row i's blocks for a given model (its table's `linearise` entry, force_model_kernels.hpp); op
// must hold the rows' zeroed blocks (reference_linear_operator allocates them). Rows marked
// kNoRow are not written, and centres that reach none of the other rows are not visited.
// Parallel over centres and the same bit for bit at every thread count: each centre's sets are
// summed, in the serial order, into the thread's local blocks (one per pair of the centre's
// points, column_table), which are then added to the global rows in centre order (an ordered
// loop; under own_family only the centre's own row is written, so no order is needed). Against
// the serial, set-by-set assembly (reference/linear_operator.hpp) only the association of the
// sums differs: equal to round-off (tests/test_linear_operator.cpp).
template <class Model>
void assemble_linear_operator_of(const Model& model, const Body& body, LinearOperator& op) {
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(body.size());
  const bool sets = (Model::kTriangles && model.has_triangles()) ||
                    (Model::kTetrahedra && model.has_tetrahedra());
  // By the body's key, as the reference kernel decides (the table follows it in a case).
  const bool energy_consistent = body.force_form == ForceForm::energy_consistent;
  const bool only_centre = !energy_consistent;
  // The tetrahedra of a volume-measure model in the vector loop (linear_operator_tetrahedra.hpp).
  constexpr bool kVolumeTetrahedra = requires {
    requires Model::kVolumeTetrahedra;
  };
  const bool vector_tetrahedra = kVolumeTetrahedra && Model::kTetrahedra && model.has_tetrahedra();
  std::exception_ptr error;
  std::atomic<bool> failed{false};
  // The centres whose sets reach an assembled row, listed first, so that the ordered loop below
  // (energy_consistent) hands over only at those (each hand-over wakes a sleeping thread: over
  // every centre the loop took longer at 2 threads than at 1, sphere-disc m = 4.015).
  std::vector<std::uint32_t> writers;
  for (std::ptrdiff_t c = 0; c < n; ++c)
    if (linear_operator_detail::writes_assembled_row(op, body, static_cast<std::size_t>(c),
                                                     only_centre))
      writers.push_back(static_cast<std::uint32_t>(c));
  const std::ptrdiff_t n_writers = static_cast<std::ptrdiff_t>(writers.size());
#pragma omp parallel
  {
    FamilyScratch s;
    std::vector<std::size_t> table;
    std::vector<Eigen::Matrix3d> local;  // zero between centres (apply_local zeroes it)
    linear_operator_detail::VolumeTetrahedronBlocks tetrahedra;
    std::vector<double> row_volume;
    // Centre c's tetrahedra into `local`, -c_t / (V row_v) G_v G_w^T: c_t = w3 (own_family,
    // rows of 1) or V^c w3 / 4 (energy_consistent, rows of V^v), as for_each_set's scales.
    auto add_tetrahedra = [&](std::ptrdiff_t c, std::size_t m) {
      if constexpr (Model::kTetrahedra) {
        const double w3 = model.tetrahedron_force_weight(body.dv3[static_cast<std::size_t>(c)]);
        const double weight =
            energy_consistent ? body.volume[static_cast<std::size_t>(c)] * w3 / 4 : w3;
        tetrahedra.prepare(m);
        if (only_centre)
          linear_operator_detail::accumulate_volume_tetrahedra<true>(s, body.degenerate_fraction,
                                                                     weight, tetrahedra);
        else
          linear_operator_detail::accumulate_volume_tetrahedra<false>(s, body.degenerate_fraction,
                                                                      weight, tetrahedra);
        row_volume.assign(m, 1.0);
        if (energy_consistent) {
          row_volume[0] = body.volume[static_cast<std::size_t>(c)];
          for (std::size_t a = 0; a + 1 < m; ++a) row_volume[1 + a] = body.volume[s.index[a]];
        }
        linear_operator_detail::add_volume_tetrahedra_to_local(
            local.data(), table, row_volume.data(), only_centre, tetrahedra);
      }
    };
    // Centre c's sets into `local`; false once some centre has thrown (the error is kept).
    auto accumulate = [&](std::ptrdiff_t c) {
      if (failed.load(std::memory_order_relaxed)) return false;
      try {
        s.load(body, static_cast<std::size_t>(c), body.damage_enabled, sets);
        const std::uint32_t centre = static_cast<std::uint32_t>(c);
        linear_operator_detail::column_table(body, centre, s, table);
        const std::size_t m = s.size() + 1;
        if (local.size() < m * m) local.resize(m * m, Eigen::Matrix3d::Zero());
        linear_operator_detail::for_each_set(
            model, body, static_cast<std::size_t>(c), s,
            [&](const auto& lin, const auto& vertex, const auto& slot, const auto& scale) {
              (void)vertex;
              linear_operator_detail::add_set_local(local.data(), lin, slot, table, m, scale,
                                                    only_centre);
            },
            !vector_tetrahedra);
        if (vector_tetrahedra) add_tetrahedra(c, m);
        return true;
      } catch (...) {
#pragma omp critical(ckpd_linear_operator_error)
        if (!error) error = std::current_exception();
        failed = true;
        return false;
      }
    };
    if (energy_consistent) {
#pragma omp for ordered schedule(dynamic, 1)
      for (std::ptrdiff_t w = 0; w < n_writers; ++w) {
        const std::uint32_t c = writers[static_cast<std::size_t>(w)];
        const bool ok = accumulate(c);
#pragma omp ordered
        if (ok) linear_operator_detail::apply_local(op, c, s, table, local.data(), false);
      }
    } else {
#pragma omp for schedule(dynamic, 16)
      for (std::ptrdiff_t w = 0; w < n_writers; ++w) {
        const std::uint32_t c = writers[static_cast<std::size_t>(w)];
        if (accumulate(c)) linear_operator_detail::apply_local(op, c, s, table, local.data(), true);
      }
    }
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace ckpd
