#include "bodies/point_stress.hpp"

#include <cstring>
#include <stdexcept>
#include <string>

#include "bodies/ckpd_model.hpp"
#include "bodies/force_model.hpp"
#include "bodies/pmb_model.hpp"
#include "bodies/state_based_model.hpp"

namespace ckpd {

namespace {

template <class Model>
Eigen::Matrix3d stress_of(const Model& model, const Body& body, std::size_t i, FamilyScratch& s) {
  const bool pairs = Model::kTriangles && model.has_triangles();
  const bool triples = Model::kTetrahedra && model.has_tetrahedra();
  s.load(body, i, body.damage_enabled, pairs || triples);
  const double degenerate = body.degenerate_fraction;
  // sum over sets of (share) k f_c (x) x_c, negated at the end.
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  const double k1 = 0.5 * body.dv1[i];  // a bond's share 1/2, force weight dV1
  for (std::size_t a = 0; a < s.size(); ++a) {
    const SetTerm<2> t = model.bond_term(s.ref[a], s.cur[a]);
    m.noalias() += k1 * t.force[1] * s.cur[a].transpose();
  }
  if constexpr (Model::kTriangles) {
    if (pairs) {
      const double k2 = model.triangle_force_weight(body.dv2[i]) / 3;
      s.for_each_pair([&](std::size_t a, std::size_t c) {
        const SetTerm<3> t =
            model.triangle_term(s.ref[a], s.ref[c], s.cur[a], s.cur[c], degenerate);
        if (t.degenerate) return;
        m.noalias() += k2 * (t.force[1] * s.cur[a].transpose() + t.force[2] * s.cur[c].transpose());
      });
    }
  }
  if constexpr (Model::kTetrahedra) {
    if (triples) {
      const double k3 = model.tetrahedron_force_weight(body.dv3[i]) / 4;
      s.for_each_triple([&](std::size_t a, std::size_t c, std::size_t d) {
        const SetTerm<4> t = model.tetrahedron_term(s.ref[a], s.ref[c], s.ref[d], s.cur[a],
                                                    s.cur[c], s.cur[d], degenerate);
        if (t.degenerate) return;
        m.noalias() += k3 * (t.force[1] * s.cur[a].transpose() + t.force[2] * s.cur[c].transpose() +
                             t.force[3] * s.cur[d].transpose());
      });
    }
  }
  return -m;
}

}  // namespace

Eigen::Matrix3d point_kirchhoff_stress(const Body& body, std::size_t i, FamilyScratch& scratch) {
  if (body.family.offset.size() != body.size() + 1)
    throw std::invalid_argument("body '" + body.name + "' has no families (a rigid body)");
  const ForceModelKernels& kernels = force_model(body);
  // Both force forms share the own-family energy (THEORY.md section 2b), so its virial is the
  // stress of either.
  if (&kernels == &ckpd_kernels() || &kernels == &ckpd_conservative_kernels())
    return stress_of(CkpdModel::of(body), body, i, scratch);
  if (&kernels == &ckpd_seth_hill_kernels() || &kernels == &ckpd_seth_hill_conservative_kernels())
    return stress_of(CkpdSethHillModel::of(body), body, i, scratch);
  if (std::strcmp(kernels.name, PmbModel::kName) == 0)
    return stress_of(PmbModel::of(body), body, i, scratch);
  if (&kernels == &state_based_kernels()) return state_based_point_kirchhoff_stress(body, i);
  throw std::invalid_argument(std::string("no per-point stress for the force model '") +
                              kernels.name + "' (body '" + body.name + "')");
}

void kirchhoff_stress(const Body& body, std::vector<Eigen::Matrix3d>& out) {
  out.assign(body.size(), Eigen::Matrix3d::Zero());
  if (body.size() == 0) return;
  {
    FamilyScratch first;  // throws here, outside the parallel region, for a body without a stress
    out[0] = point_kirchhoff_stress(body, 0, first);
  }
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(body.size());
#pragma omp parallel
  {
    FamilyScratch scratch;
#pragma omp for schedule(dynamic, 64)
    for (std::ptrdiff_t i = 1; i < n; ++i)
      out[static_cast<std::size_t>(i)] =
          point_kirchhoff_stress(body, static_cast<std::size_t>(i), scratch);
  }
}

}  // namespace ckpd
