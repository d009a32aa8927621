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

// The operator with the rows of the points p with first[p] == p assembled (their blocks in point
// order) and every other point sharing the row of first[p].
LinearOperator assemble_rows(const Body& body, const std::vector<std::uint32_t>& first) {
  const ForceModelKernels& kernels = linearisable_model(body);
  const std::size_t n = body.size();
  LinearOperator op;
  op.row.assign(n, LinearOperator::kNoRow);
  std::size_t blocks = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (first[i] == i) {
      op.row[i] = blocks;
      blocks += 1 + body.family.family_size(i);
      ++op.classes;
    }
  op.block.assign(blocks, Eigen::Matrix3d::Zero());
  kernels.linearise(body, op);
  for (std::size_t i = 0; i < n; ++i) op.row[i] = op.row[first[i]];
  return op;
}
}  // namespace

LinearOperator reference_linear_operator(const Body& body) {
  std::vector<std::uint32_t> own(body.size());
  for (std::size_t i = 0; i < own.size(); ++i) own[i] = static_cast<std::uint32_t>(i);
  return assemble_rows(body, own);
}

LinearOperator linear_operator_by_class(const Body& body) {
  linearisable_model(body);  // the model's error before the classes' work
  return assemble_rows(body, operator_row_classes(body));
}

namespace {
// Row i of K times the body's displacements.
Vec3 row_product(const LinearOperator& op, const Body& body, std::size_t i) {
  const Eigen::Matrix3d* row = &op.block[op.row[i]];
  Vec3 sum = row[0] * body.displacement[i];
  std::size_t slot = 1;
  for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k, ++slot)
    sum += row[slot] * body.displacement[body.family.neighbour[k]];
  return sum;
}
}  // namespace

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
  for (std::size_t i = 0; i < n; ++i) b[i] = row_product(op, body, i);
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
