// Which rows of a body's arrays a process writes into a frame or checkpoint
// (src/output/output_share.hpp; issue 14): one process writes every row, as one run of points
// and one of bonds, and the rows it picks are the body's in order.
#include <catch2/catch.hpp>

#include "run_helpers.hpp"
#include "src/case/case_loader.hpp"
#include "src/output/output_share.hpp"

using namespace ckpd;
using namespace ckpd::testing;

TEST_CASE("a row share merges adjacent runs and counts its rows", "[output][mpi]") {
  hdf5::RowShare share = hdf5::RowShare::none(20);
  CHECK(share.mine() == 0);
  share.add(2, 3);
  share.add(5, 1);  // adjacent: one run 2..5
  share.add(8, 0);  // nothing
  share.add(9, 4);
  REQUIRE(share.runs.size() == 2);
  CHECK(share.runs[0] == std::pair<std::size_t, std::size_t>{2, 4});
  CHECK(share.runs[1] == std::pair<std::size_t, std::size_t>{9, 4});
  CHECK(share.mine() == 8);
  CHECK(share.rows == 20);
  const hdf5::RowShare all = hdf5::RowShare::all(7);
  REQUIRE(all.runs.size() == 1);
  CHECK(all.mine() == 7);
  CHECK(hdf5::RowShare::all(0).runs.empty());
}

TEST_CASE("one process's share of a body is every point and bond in order", "[output][mpi]") {
  const auto dir = fresh_dir("output-share");
  Scene scene = load_scene(write_file(dir / "case.yaml", R"(# SI units
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.2, fracture_energy: 50}
bodies:
  - {name: strip, material: steel, dimension: 2, geometry: {type: box, min: [0, 0], max: [0.006, 0.004]},
     spacing: 0.001, horizon_ratio: 2.015}
time: {steps: 1}
)"));
  Simulation sim(scene);
  Body& body = scene.bodies[0].body;
  for (std::size_t k = 0; k < body.bond_intact.size(); k += 3) body.bond_intact[k] = 0;
  const BodyShare share = body_share(sim, 0);
  CHECK_FALSE(shared_output(sim));
  CHECK(share.body == &body);
  CHECK(share.whole_of_local == nullptr);
  REQUIRE(share.points.runs.size() == 1);
  CHECK(share.points.mine() == body.size());
  REQUIRE(share.bonds.runs.size() == 1);
  CHECK(share.bonds.mine() == body.bond_intact.size());
  CHECK(bond_rows(share) == body.bond_intact);
  std::vector<double> values(2 * body.size());
  for (std::size_t k = 0; k < values.size(); ++k) values[k] = static_cast<double>(k);
  std::vector<double> scratch;
  CHECK(&rows_of(share, values, 2, scratch) == &values);  // every point: no copy
  CHECK(share.whole_index(5) == 5);
  // A share of points 1 and 3 (a rank's owned points) takes their rows, in order.
  BodyShare part = share;
  part.local = {1, 3};
  CHECK(rows_of(part, values, 2, scratch) == std::vector<double>{2, 3, 6, 7});
}
