#include "bodies/far_field.hpp"

#include <algorithm>
#include <limits>

namespace ckpd {

FarField make_far_field(const Body& body, double tolerance, bool corotated) {
  FarField ff;
  ff.tolerance = tolerance;
  ff.op = linear_operator_by_class(body);
  const std::size_t n = body.size();
  ff.exact.assign(n, 0);
  ff.row_failed.assign(n, 0);
  ff.skip.assign(n, 0);
  ff.corotated = corotated;
  ff.shortest_bond2.assign(n, std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k)
      ff.shortest_bond2[i] =
          std::min(ff.shortest_bond2[i],
                   (body.reference_position[body.family.neighbour[k]] - body.reference_position[i])
                       .squaredNorm());
  if (!corotated) {
    ff.linear_force.assign(n, Vec3::Zero());  // filled by the classification
    return ff;
  }
  ff.shape_inverse.assign(n, Eigen::Matrix3d::Zero());
  ff.rotation.assign(n, Eigen::Matrix3d::Identity());
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k) {
      const Vec3 dX =
          body.reference_position[body.family.neighbour[k]] - body.reference_position[i];
      A += dX * dX.transpose();
    }
    // In the plane: any positive out-of-plane entry leaves F's out-of-plane entry at 1 (its
    // row and column of sum_j du dX^T are zero); the in-plane mean keeps A's scale.
    if (body.dimension == 2) A(2, 2) = 0.5 * (A(0, 0) + A(1, 1));
    // A family that spans no volume (area) has no rotation to take out: exact throughout.
    const double scale = A.trace();
    if (!(scale > 0) || !(A.determinant() > 1e-9 * scale * scale * scale)) {
      ff.exact[i] = 1;
      continue;
    }
    ff.shape_inverse[i] = A.inverse();
  }
  ff.exact_count = static_cast<std::size_t>(std::count(ff.exact.begin(), ff.exact.end(), 1));
  return ff;
}

bool polar_rotation(const Eigen::Matrix3d& F, Eigen::Matrix3d& R) {
  if (!(F.determinant() > 0)) return false;
  Eigen::Matrix3d X = F;
  for (int k = 0; k < 30; ++k) {
    const Eigen::Matrix3d next = 0.5 * (X + X.inverse().transpose());
    const double change = (next - X).squaredNorm();
    X = next;
    if (change < 1e-30) break;  // |R|^2 = 3: converged to round-off
  }
  R = X;
  return true;
}

namespace {

// Corotated screen of point i: R^i from its family's deformation gradient, then
// max_j |R^iT dx^ij - dX^ij|^2 / L^2 (+inf for an inverted family).
double corotated_screen(const Body& body, FarField& ff, std::size_t i) {
  const std::size_t* offset = body.family.offset.data();
  const std::uint32_t* nb = body.family.neighbour.data();
  const Vec3 Xi = body.reference_position[i], ui = body.displacement[i];
  Eigen::Matrix3d G = Eigen::Matrix3d::Zero();  // sum_j (u^j - u^i) dX^T
  for (std::size_t k = offset[i]; k < offset[i + 1]; ++k) {
    const std::uint32_t j = nb[k];
    G += (body.displacement[j] - ui) * (body.reference_position[j] - Xi).transpose();
  }
  const Eigen::Matrix3d F = Eigen::Matrix3d::Identity() + G * ff.shape_inverse[i];
  Eigen::Matrix3d& R = ff.rotation[i];
  if (!polar_rotation(F, R)) return std::numeric_limits<double>::infinity();
  const Eigen::Matrix3d Rt = R.transpose(), Qt = Rt - Eigen::Matrix3d::Identity();
  double worst = 0;
  for (std::size_t k = offset[i]; k < offset[i + 1]; ++k) {
    const std::uint32_t j = nb[k];
    const double L2 = (body.reference_position[j] - Xi).squaredNorm();
    worst = std::max(worst, corotated_relative(body, Rt, Qt, i, j).squaredNorm() / L2);
  }
  return worst;
}

}  // namespace

namespace {

// A failed bond with both ends in {i} and i's family makes i exact. Row i of the operator is
// built from the sets that hold i, and every edge of such a set is a bond between two points of
// {i} and its family (all its vertices are bonded to i): a failed bond with an end outside
// switches none of them off, and row i stays as assembled. Members' rows with a failed bond are
// searched only where row_failed says there is one.
bool failed_bond_among_family(const Body& body, const FarField& ff, std::size_t i) {
  const std::size_t* offset = body.family.offset.data();
  const std::uint32_t* nb = body.family.neighbour.data();
  const std::uint8_t* intact = body.bond_intact.data();
  const std::uint32_t* first = nb + offset[i];
  const std::uint32_t* last = nb + offset[i + 1];
  for (const std::uint32_t* p = first; p < last; ++p) {
    const std::uint32_t j = *p;
    if (!ff.row_failed[j]) continue;
    for (std::size_t k = offset[j]; k < offset[j + 1]; ++k)
      if (intact[k] == 0 && (nb[k] == i || std::binary_search(first, last, nb[k]))) return true;
  }
  return false;
}

// The plain screen max_j |u^j - u^i|^2 / L^2 < T^2, bond by bond.
bool passes_screen(const Body& body, std::size_t i, double T2) {
  const std::size_t* offset = body.family.offset.data();
  const std::uint32_t* nb = body.family.neighbour.data();
  const Vec3 Xi = body.reference_position[i], ui = body.displacement[i];
  double worst = 0;
  for (std::size_t k = offset[i]; k < offset[i + 1]; ++k) {
    const std::uint32_t j = nb[k];
    const double L2 = (body.reference_position[j] - Xi).squaredNorm();
    worst = std::max(worst, (body.displacement[j] - ui).squaredNorm() / L2);
  }
  return worst < T2;
}

}  // namespace

void classify_far_field(const Body& body, FarField& ff) {
  const std::size_t n = body.size();
  const std::size_t* offset = body.family.offset.data();
  const std::uint32_t* nb = body.family.neighbour.data();
  const std::uint8_t* intact = body.damage_enabled ? body.bond_intact.data() : nullptr;
  const bool moved = !body.displacement.empty();
  const double T2 = ff.tolerance * ff.tolerance;
  std::size_t exact_count = 0;
  if (!ff.corotated) ff.linear_force.resize(n);  // make_far_field sized it: no allocation
#pragma omp parallel
  {
    // A failed bond anywhere in i's row (read for i's members below: a pass of its own).
    if (intact != nullptr) {
#pragma omp for schedule(static)
      for (std::size_t i = 0; i < n; ++i) {
        std::uint8_t failed = 0;
        for (std::size_t k = offset[i]; k < offset[i + 1]; ++k) failed |= intact[k] == 0;
        ff.row_failed[i] = failed;
      }
    }
#pragma omp for schedule(dynamic, 256)
    for (std::size_t i = 0; i < n; ++i) {
      if (ff.exact[i]) continue;
      if (intact != nullptr && ff.row_failed[i]) {
        ff.exact[i] = 1;
        continue;
      }
      // Whether a member's row has a failed bond (then the search below); read in the screen's
      // pass where there is one.
      bool member_failed = intact != nullptr;
      if (!moved) {  // at the reference state: no strain, and b^i = K 0
        if (!ff.corotated) ff.linear_force[i] = Vec3::Zero();
      } else if (ff.corotated) {
        if (!(corotated_screen(body, ff, i) < T2)) {
          ff.exact[i] = 1;
          continue;
        }
      } else {
        // b^i = K^ii u^i + sum_j K^ij u^j summed as apply_linear_operator sums it (row_product;
        // the tests compare the two bit for bit), and the screen bounded through the family's
        // shortest bond: max_j |u^j - u^i|^2 < T^2 L_min^2 (1 - 1e-12) makes every |u^j - u^i|^2 /
        // L^2, rounded, less than T^2: the bond-by-bond screen's decision without its divisions.
        // Only a point near or past the tolerance takes the bond-by-bond screen.
        const Vec3 ui = body.displacement[i];
        double most = 0;  // max_j |u^j - u^i|^2
        std::uint8_t failed = 0;
        const Vec3 b = row_product(ff.op, body, i, [&](std::uint32_t j, const Vec3& uj) {
          most = std::max(most, (uj - ui).squaredNorm());
          if (intact != nullptr) failed |= ff.row_failed[j];
        });
        ff.linear_force[i] = b;
        member_failed = failed != 0;
        if (!(most < T2 * ff.shortest_bond2[i] * (1 - 1e-12)) && !passes_screen(body, i, T2)) {
          ff.exact[i] = 1;
          continue;
        }
      }
      if (member_failed && failed_bond_among_family(body, ff, i)) ff.exact[i] = 1;
    }
    // Centre i is skipped when i and every upper neighbour (j > i) are linear.
#pragma omp for schedule(static) reduction(+ : exact_count)
    for (std::size_t i = 0; i < n; ++i) {
      std::uint8_t any = ff.exact[i];
      exact_count += any;
      const std::uint32_t* end = nb + offset[i + 1];
      for (const std::uint32_t* p =
               std::upper_bound(nb + offset[i], end, static_cast<std::uint32_t>(i));
           p < end && !any; ++p)
        any = ff.exact[*p];
      ff.skip[i] = !any;
    }
  }
  ff.exact_count = exact_count;
}

SymmetricKernelStats compute_internal_force_far_field(Body& body, FarField& ff, bool with_energy,
                                                      SymmetricKernelWorkspace& workspace) {
  classify_far_field(body, ff);
  workspace.skip_centre = ff.skip.data();
  workspace.exact_point = ff.mask_sets ? ff.exact.data() : nullptr;
  SymmetricKernelStats stats;
  try {
    stats = compute_internal_force_symmetric(body, with_energy, workspace);
  } catch (...) {
    workspace.skip_centre = nullptr;
    workspace.exact_point = nullptr;
    throw;
  }
  workspace.skip_centre = nullptr;
  workspace.exact_point = nullptr;
  if (ff.corotated) {
    apply_linear_operator_rows_corotated(ff.op, body, ff.exact.data(), ff.rotation,
                                         body.force_density);
  } else {
    const std::size_t n = body.size();
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i)
      if (!ff.exact[i]) body.force_density[i] = ff.linear_force[i];
  }
  if (with_energy) {
    const std::size_t n = body.size();
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i)
      if (!ff.exact[i])
        body.strain_energy_density[i] =
            ff.corotated ? linear_energy_density_corotated(ff.op, body, i, ff.rotation[i])
                         : linear_energy_density(ff.op, body, i);
  }
  return stats;
}

SymmetricKernelStats compute_internal_force_far_field(Body& body, FarField& ff, bool with_energy) {
  thread_local SymmetricKernelWorkspace workspace;
  return compute_internal_force_far_field(body, ff, with_energy, workspace);
}

}  // namespace ckpd
