#include "reference/internal_force.hpp"

#include <vector>

#include "bodies/ckpd_model.hpp"

namespace ckpd {

namespace {

// ForceForm::energy_consistent, straight from its definition (THEORY.md section 2b):
//   E = sum_c V^c (W1^c / 2 + W2^c / 3 + W3^c / 4),  b^d = -(1/V^d) dE/dx^d.
// Every point c walks its own family (the sets active for c under the damage rule and
// non-degenerate from c, as evaluate_point does) and gives every vertex d of each set the
// gradient of that set's share of c's energy, V^c / (n + 1) times the set's term in W_n^c
// (force weight times the term per unit force weight), divided by V^d. Serial: plain.
template <class Model>
void conservative_forces(const Model& model, Body& body) {
  const std::size_t n = body.size();
  std::vector<Vec3> b(n, Vec3::Zero());
  const bool pairs = Model::kTriangles && model.has_triangles();
  const bool triples = Model::kTetrahedra && model.has_tetrahedra();
  const double degenerate = body.degenerate_fraction;
  const std::vector<double>& V = body.volume;
  FamilyScratch s;
  for (std::size_t c = 0; c < n; ++c) {
    s.load(body, c, body.damage_enabled, pairs || triples);
    const double Vc = V[c];
    const double w1 = body.dv1[c] * Vc / 2;  // W1^c / 2: one order per bond
    for (std::size_t a = 0; a < s.size(); ++a) {
      const SetTerm<2> t = model.bond_term(s.ref[a], s.cur[a]);
      b[c] += w1 / Vc * t.force[0];
      b[s.index[a]] += w1 / V[s.index[a]] * t.force[1];
    }
    if constexpr (Model::kTriangles) {
      if (pairs) {
        const double w2 = model.triangle_force_weight(body.dv2[c]) * Vc / 3;
        s.for_each_pair([&](std::size_t a, std::size_t e) {
          const SetTerm<3> t =
              model.triangle_term(s.ref[a], s.ref[e], s.cur[a], s.cur[e], degenerate);
          if (t.degenerate) return;
          b[c] += w2 / Vc * t.force[0];
          b[s.index[a]] += w2 / V[s.index[a]] * t.force[1];
          b[s.index[e]] += w2 / V[s.index[e]] * t.force[2];
        });
      }
    }
    if constexpr (Model::kTetrahedra) {
      if (triples) {
        const double w3 = model.tetrahedron_force_weight(body.dv3[c]) * Vc / 4;
        s.for_each_triple([&](std::size_t a, std::size_t e, std::size_t f) {
          const SetTerm<4> t = model.tetrahedron_term(s.ref[a], s.ref[e], s.ref[f], s.cur[a],
                                                      s.cur[e], s.cur[f], degenerate);
          if (t.degenerate) return;
          b[c] += w3 / Vc * t.force[0];
          b[s.index[a]] += w3 / V[s.index[a]] * t.force[1];
          b[s.index[e]] += w3 / V[s.index[e]] * t.force[2];
          b[s.index[f]] += w3 / V[s.index[f]] * t.force[3];
        });
      }
    }
  }
  body.force_density = std::move(b);
}

}  // namespace

void compute_internal_force(Body& body, bool with_energy) {
  const std::size_t n = body.size();
  const bool conservative = body.force_form == ForceForm::energy_consistent;
#pragma omp parallel
  {
    FamilyScratch scratch;
    // Dynamic chunks: points near surfaces and cracks have far fewer interactions.
#pragma omp for schedule(dynamic, 32)
    for (std::size_t i = 0; i < n; ++i) {
      if (!conservative || with_energy) {
        const PointResult r = evaluate_point(body, i, scratch);
        if (!conservative) body.force_density[i] = r.force_density;
        // The own-family energies: E is their volume-weighted sum in both force forms.
        if (with_energy) body.strain_energy_density[i] = r.strain_energy_density();
      }
    }
  }
  if (!conservative) return;
  if (body.strain_measure != 0.5) {
    conservative_forces(CkpdSethHillModel::of(body), body);
  } else {
    conservative_forces(CkpdModel::of(body), body);
  }
}

}  // namespace ckpd
