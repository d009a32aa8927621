// The census's vector loop over the tetrahedra (census.hpp, add_volume_tetrahedron_bounds)
// against the set-by-set loop over the model's own linearisations: the same interaction counts
// (the same degenerate sets left out) and the same stiffness-bound matrices to round-off, on
// lattices (many exactly coplanar sets) and jittered clouds, at several horizons and degenerate
// fractions, every point of the body (surfaces, edges and corners included).
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "bodies/census.hpp"
#include "bodies/ckpd_model.hpp"
#include "bodies/material.hpp"
#include "body_fixtures.hpp"

using namespace ckpd;
using namespace ckpd_test;

namespace {

constexpr double kDx = 0.001;

// max |a - b| over max |b|, 0 when both are zero.
double relative(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  const double scale = b.cwiseAbs().maxCoeff();
  return scale > 0 ? (a - b).cwiseAbs().maxCoeff() / scale : a.cwiseAbs().maxCoeff();
}

}  // namespace

TEST_CASE("the census's vector loop over tetrahedra equals the set-by-set census", "[census]") {
  struct Setting {
    const char* label;
    double m, jitter, fraction;
    int n;
  };
  std::size_t tetrahedra = 0, left_out = 0;
  // kDegenerateFraction: the default; 0.05: more sets on both sides of the limit.
  for (const Setting s : {Setting{"lattice, m = 3.015", 3.015, 0.0, kDegenerateFraction, 7},
                          Setting{"lattice, m = 3.015, f = 0.05", 3.015, 0.0, 0.05, 7},
                          Setting{"cloud, m = 3.015", 3.015, 0.25, kDegenerateFraction, 7},
                          Setting{"cloud, m = 2.5, f = 0.05", 2.5, 0.3, 0.05, 6},
                          Setting{"lattice, m = 4.015", 4.015, 0.0, 1e-3, 5}}) {
    std::mt19937 rng(99);
    const InteractionConstants constants =
        interaction_constants(3, 200e9, 0.3, PlaneMode::none, s.m * kDx);
    BodyDefinition d = s.jitter > 0
                           ? jittered_cloud(3, s.n, s.n, s.n, kDx, s.m, constants, s.jitter, rng)
                           : lattice_block(3, s.n, s.n, s.n, kDx, s.m, constants);
    d.degenerate_fraction = s.fraction;
    const Body body = make_body(d);
    const CkpdModel model = CkpdModel::of(body);
    const ConservativeForm<CkpdModel> conservative(model);
    FamilyScratch scratch;
    for (std::size_t i = 0; i < body.size(); ++i) {
      scratch.load(body, i, false, true);
      const PointCensus by_set = census_point_by_set(model, scratch, s.fraction);
      const PointCensus vector = census_point_of(model, scratch, s.fraction);
      INFO(s.label << ", point " << i);
      REQUIRE(by_set.n3 > 0);
      CHECK(vector.n3 == by_set.n3);
      CHECK(vector.n2 == by_set.n2);
      CHECK(relative(vector.q3, by_set.q3) <= 1e-13);
      CHECK(vector.q1 == by_set.q1);  // bonds and triangles: the same loop
      CHECK(vector.q2 == by_set.q2);
      // The energy-consistent form has the law's linearisation: the same census.
      const PointCensus form = census_point_of(conservative, scratch, s.fraction);
      CHECK(form.n3 == vector.n3);
      CHECK(form.q3 == vector.q3);
      tetrahedra += by_set.n3 / 6;
      if (s.fraction > kDegenerateFraction) {
        const PointCensus all = census_point_by_set(model, scratch, kDegenerateFraction);
        left_out += (all.n3 - by_set.n3) / 6;
      }
    }
  }
  INFO(tetrahedra << " tetrahedra, " << left_out << " left out as degenerate");
  // The raised fractions must have left sets out, or the degenerate test was not exercised.
  CHECK(left_out > 0);
}
