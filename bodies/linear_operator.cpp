#include "bodies/linear_operator.hpp"

#include <stdexcept>
#include <string>

#include "bodies/force_model.hpp"

namespace ckpd {

LinearOperator reference_linear_operator(const Body& body) {
  const std::size_t n = body.size();
  LinearOperator op;
  op.offset.resize(n + 1);
  op.offset[0] = 0;
  for (std::size_t i = 0; i < n; ++i)
    op.offset[i + 1] = op.offset[i] + 1 + body.family.family_size(i);
  op.block.assign(op.offset[n], Eigen::Matrix3d::Zero());
  const ForceModelKernels& kernels = force_model(body);
  if (kernels.linearise == nullptr)
    throw std::invalid_argument(std::string("the '") + kernels.name +
                                "' model has no linearisation at the reference state (the far "
                                "field needs the ckpd or pmb model)");
  kernels.linearise(body, op);
  return op;
}

namespace {
// Row i of K times the body's displacements.
Vec3 row_product(const LinearOperator& op, const Body& body, std::size_t i) {
  const Eigen::Matrix3d* row = &op.block[op.offset[i]];
  Vec3 sum = row[0] * body.displacement[i];
  std::size_t slot = 1;
  for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k, ++slot)
    sum += row[slot] * body.displacement[body.family.neighbour[k]];
  return sum;
}
}  // namespace

double linear_energy_density(const LinearOperator& op, const Body& body, std::size_t i) {
  const Eigen::Matrix3d* row = &op.block[op.offset[i]];
  const Vec3 ui = body.displacement[i];
  double w = 0;
  std::size_t slot = 1;
  for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k, ++slot) {
    const Vec3 d = body.displacement[body.family.neighbour[k]] - ui;
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

void apply_linear_operator_rows(const LinearOperator& op, const Body& body,
                                const std::uint8_t* exact, std::vector<Vec3>& b) {
  const std::size_t n = body.size();
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i)
    if (!exact[i]) b[i] = row_product(op, body, i);
}

}  // namespace ckpd
