#include "bodies/linear_operator.hpp"

#include <stdexcept>
#include <string>

#include "bodies/force_model.hpp"
#include "bodies/operator_classes.hpp"

namespace ckpd {

namespace {
const ForceModelKernels& linearisable_model(const Body& body) {
  const ForceModelKernels& kernels = force_model(body);
  if (kernels.linearise == nullptr)
    throw std::invalid_argument(std::string("the '") + kernels.name +
                                "' model has no linearisation at the reference state (the far "
                                "field needs the ckpd or pmb model)");
  return kernels;
}

// Row p's blocks turned from row r's by the symmetry S (operator_classes.hpp): the block of p's
// member at offset S o is S B S^T with B the block of r's member at offset o, entry by entry
// (S B S^T)(a, b) = sign[a] sign[b] B(perm[a], perm[b]). r's members are looked up by offset in
// `table` (filled and cleared here).
void turn_row(const Body& body, const RowClasses& classes, std::size_t p, LinearOperator& op,
              std::size_t start, OffsetTable& table) {
  const std::size_t r = classes.source[p];
  const LatticeSymmetry& S = lattice_symmetries()[classes.symmetry[p]];
  const std::int32_t* coord = classes.coord.data();
  auto member = [&](std::size_t i, std::size_t a) -> std::size_t {
    return a == 0 ? i : body.family.neighbour[body.family.offset[i] + a - 1];
  };
  auto offset = [&](std::size_t i, std::size_t q) -> OffsetTable::Offset {
    return {std::int64_t{coord[3 * q]} - coord[3 * i],
            std::int64_t{coord[3 * q + 1]} - coord[3 * i + 1],
            std::int64_t{coord[3 * q + 2]} - coord[3 * i + 2]};
  };
  const std::size_t members = 1 + body.family.family_size(r);
  for (std::size_t a = 0; a < members; ++a)
    table.set(offset(r, member(r, a)), static_cast<std::int32_t>(a));
  const Eigen::Matrix3d* source = &op.block[op.row[r]];
  Eigen::Matrix3d* row = &op.block[start];
  for (std::size_t a = 0; a < members; ++a) {
    const OffsetTable::Offset o = offset(p, member(p, a));
    OffsetTable::Offset back{};  // S^T o: back[perm[d]] = sign[d] o[d]
    for (int d = 0; d < 3; ++d) back[static_cast<std::size_t>(S.perm[d])] = S.sign[d] * o[d];
    const std::int32_t slot = table.at(back);
    if (slot < 0) throw std::logic_error("linear operator: a turned row's member has no source");
    const Eigen::Matrix3d& B = source[slot];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) row[a](i, k) = S.sign[i] * S.sign[k] * B(S.perm[i], S.perm[k]);
  }
  for (std::size_t a = 0; a < members; ++a) table.set(offset(r, member(r, a)), -1);
}

// The operator with the rows of the classes' first points assembled where their source is
// themselves (their blocks in point order), turned from their source's otherwise, and every
// other point sharing the row of its class's first point.
LinearOperator assemble_rows(const Body& body, const RowClasses& classes) {
  const ForceModelKernels& kernels = linearisable_model(body);
  const std::size_t n = body.size();
  LinearOperator op;
  op.row.assign(n, LinearOperator::kNoRow);
  std::vector<std::size_t> start(n, LinearOperator::kNoRow);
  std::size_t blocks = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (classes.first[i] == i) {
      start[i] = blocks;
      blocks += 1 + body.family.family_size(i);
      ++op.classes;
      if (classes.source[i] == i) {
        op.row[i] = start[i];  // assembled
        ++op.assembled;
      }
    }
  op.block.assign(blocks, Eigen::Matrix3d::Zero());
  kernels.linearise(body, op);
  if (op.assembled < op.classes) {
    OffsetTable table(classes.reach);
    for (std::size_t i = 0; i < n; ++i)
      if (classes.first[i] == i && classes.source[i] != i)
        turn_row(body, classes, i, op, start[i], table);
  }
  for (std::size_t i = 0; i < n; ++i) op.row[i] = start[classes.first[i]];
  return op;
}
}  // namespace

LinearOperator reference_linear_operator(const Body& body) {
  RowClasses own;
  own.first.resize(body.size());
  for (std::size_t i = 0; i < own.first.size(); ++i) own.first[i] = static_cast<std::uint32_t>(i);
  own.source = own.first;
  return assemble_rows(body, own);
}

LinearOperator linear_operator_by_class(const Body& body) {
  linearisable_model(body);  // the model's error before the classes' work
  return assemble_rows(body, operator_row_classes(body));
}

double linear_energy_density(const LinearOperator& op, const Body& body, std::size_t i) {
  const Eigen::Matrix3d* row = &op.block[op.row[i]];
  const Vec3 ui = body.displacement[i];
  double w = 0;
  std::size_t slot = 1;
  for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k, ++slot) {
    const Vec3 d = body.displacement[body.family.neighbour[k]] - ui;
    w += d.dot(row[slot] * d);
  }
  return 0.25 * w;
}

double linear_energy_density_corotated(const LinearOperator& op, const Body& body, std::size_t i,
                                       const Eigen::Matrix3d& R) {
  const Eigen::Matrix3d* row = &op.block[op.row[i]];
  const Eigen::Matrix3d Rt = R.transpose(), Qt = Rt - Eigen::Matrix3d::Identity();
  double w = 0;
  std::size_t slot = 1;
  for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k, ++slot) {
    const Vec3 d = corotated_relative(body, Rt, Qt, i, body.family.neighbour[k]);
    w += d.dot(row[slot] * d);
  }
  return 0.25 * w;
}

void apply_linear_operator(const LinearOperator& op, const Body& body, std::vector<Vec3>& b) {
  const std::size_t n = body.size();
  b.resize(n);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i)
    b[i] = row_product(op, body, i, [](std::size_t, const Vec3&) {});
}

void apply_linear_operator_rows_corotated(const LinearOperator& op, const Body& body,
                                          const std::uint8_t* exact,
                                          const std::vector<Eigen::Matrix3d>& rotation,
                                          std::vector<Vec3>& b) {
  const std::size_t n = body.size();
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    if (exact[i]) continue;
    // Row i's blocks sum to zero over its columns (a translation gives no force), so the row
    // acts on the relative displacements alone.
    const Eigen::Matrix3d* row = &op.block[op.row[i]];
    const Eigen::Matrix3d& R = rotation[i];
    const Eigen::Matrix3d Rt = R.transpose(), Qt = Rt - Eigen::Matrix3d::Identity();
    Vec3 sum = Vec3::Zero();
    std::size_t slot = 1;
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k, ++slot)
      sum += row[slot] * corotated_relative(body, Rt, Qt, i, body.family.neighbour[k]);
    b[i] = R * sum;
  }
}

}  // namespace ckpd
