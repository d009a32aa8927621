// The spatial decomposition over ranks (src/engine/decomposition.hpp): every deformable point
// has one owner, the cuts balance the interaction work (not the point count), the cut of two
// ranks is perpendicular to the longest axis, a rank's halo is exactly the other ranks' points
// within a horizon of its own (brute-force distance check), and too many ranks are refused.
// `ckpd check --ranks N` prints it.
#include <algorithm>
#include <catch2/catch.hpp>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "bodies/body.hpp"
#include "kernel_comparison.hpp"
#include "run_helpers.hpp"
#include "src/engine/decomposition.hpp"
#include "src/output/hdf5_io.hpp"

using ckpd::Body;
using ckpd::Decomposition;
using ckpd::Vec3;

namespace {

Body block_body(int dimension, int nx, int ny, int nz, double m, double jitter = 0,
                Vec3 shift = Vec3::Zero()) {
  using namespace kernel_comparison;
  std::mt19937 rng(5);
  const double nu = dimension == 3 ? 0.3 : 0.4;
  InteractionConstants c = ckpd::interaction_constants(
      dimension, kE, nu, dimension == 2 ? PlaneMode::stress : PlaneMode::none, m * kDx);
  ckpd::BodyDefinition d = block(dimension, nx, ny, nz, c, jitter, rng, m);
  for (Vec3& x : d.reference_position) x += shift;
  return ckpd::make_body(d);
}

Decomposition decompose_one(const Body& body, int ranks) {
  return ckpd::decompose({&body}, {false}, ranks);
}

}  // namespace

TEST_CASE("every deformable point has exactly one owner and every rank owns some",
          "[decomposition]") {
  const Body body = block_body(3, 12, 8, 6, 2.015);
  for (int ranks = 1; ranks <= 5; ++ranks) {
    const Decomposition d = decompose_one(body, ranks);
    std::vector<std::uint64_t> owned(static_cast<std::size_t>(ranks), 0);
    for (const int r : d.owner[0]) {
      REQUIRE(r >= 0);
      REQUIRE(r < ranks);
      ++owned[static_cast<std::size_t>(r)];
    }
    std::uint64_t sum = 0;
    for (int r = 0; r < ranks; ++r) {
      CHECK(owned[static_cast<std::size_t>(r)] > 0);
      CHECK(owned[static_cast<std::size_t>(r)] == d.share[static_cast<std::size_t>(r)].points);
      sum += owned[static_cast<std::size_t>(r)];
    }
    CHECK(sum == body.size());
    // Deterministic: the same input gives the same owners.
    CHECK(decompose_one(body, ranks).owner == d.owner);
  }
}

TEST_CASE("the cuts balance the interaction work, not the point count", "[decomposition]") {
  // A block with a three-neighbour family (m = 3.015) next to one of the same size with a small
  // one (m = 1.515): per point the first costs several times the second.
  const Body heavy = block_body(3, 8, 8, 8, 3.015);
  const Body light = block_body(3, 8, 8, 8, 1.515, 0, Vec3(8e-3, 0, 0));
  REQUIRE(ckpd::point_work(heavy, 0) > 0);
  const Decomposition d = ckpd::decompose({&heavy, &light}, {false, false}, 2);
  INFO("imbalance " << d.imbalance() << ", points " << d.share[0].points << " / "
                    << d.share[1].points);
  CHECK(d.imbalance() < 1.02);
  // The rank that holds the heavy block holds fewer points.
  const int heavy_rank = d.owner[0][0];
  CHECK(d.share[static_cast<std::size_t>(heavy_rank)].points <
        d.share[static_cast<std::size_t>(1 - heavy_rank)].points);
  for (const int ranks : {3, 4}) {
    const Body one = block_body(3, 16, 8, 8, 3.015);
    const Decomposition e = decompose_one(one, ranks);
    INFO(ranks << " ranks: imbalance " << e.imbalance());
    CHECK(e.imbalance() < 1.03);
  }
}

TEST_CASE("two ranks cut a bar across its longest axis", "[decomposition]") {
  const Body bar = block_body(3, 30, 5, 4, 2.015);
  const Decomposition d = decompose_one(bar, 2);
  double hi0 = -1e9, lo0 = 1e9, hi1 = -1e9, lo1 = 1e9;
  for (std::size_t i = 0; i < bar.size(); ++i) {
    const double x = bar.reference_position[i].x();
    (d.owner[0][i] == 0 ? hi0 : hi1) = std::max(d.owner[0][i] == 0 ? hi0 : hi1, x);
    (d.owner[0][i] == 0 ? lo0 : lo1) = std::min(d.owner[0][i] == 0 ? lo0 : lo1, x);
  }
  CHECK((hi0 < lo1 || hi1 < lo0));
}

TEST_CASE("a rank's halo is the other ranks' points within a horizon of its own",
          "[decomposition]") {
  for (const int dimension : {2, 3}) {
    const Body body =
        dimension == 2 ? block_body(2, 20, 14, 1, 3.015, 0.2) : block_body(3, 10, 8, 6, 2.015, 0.2);
    const double limit = body.horizon * (1 + ckpd::kHorizonTolerance);
    for (const int ranks : {1, 3}) {
      const Decomposition d = decompose_one(body, ranks);
      for (int r = 0; r < ranks; ++r) {
        std::set<std::size_t> ghosts;
        for (std::size_t i = 0; i < body.size(); ++i) {
          if (d.owner[0][i] != r) continue;
          for (std::size_t j = 0; j < body.size(); ++j)
            if (d.owner[0][j] != r && j != i &&
                (body.reference_position[j] - body.reference_position[i]).norm() <= limit)
              ghosts.insert(j);
        }
        INFO(dimension << "D, " << ranks << " ranks, rank " << r);
        CHECK(d.share[static_cast<std::size_t>(r)].ghosts == ghosts.size());
        if (ranks == 1) CHECK(ghosts.empty());
        if (ranks > 1) CHECK(!ghosts.empty());
      }
    }
  }
}

TEST_CASE("rigid bodies are not decomposed and too many ranks are refused", "[decomposition]") {
  const Body small = block_body(3, 2, 2, 2, 2.015);
  const Body rigid = block_body(3, 3, 3, 3, 2.015, 0, Vec3(1, 0, 0));
  const Decomposition d = ckpd::decompose({&small, &rigid}, {false, true}, 8);
  for (const int r : d.owner[1]) CHECK(r == -1);
  try {
    ckpd::decompose({&small, &rigid}, {false, true}, 9);
    FAIL("9 ranks for 8 deformable points were accepted");
  } catch (const std::invalid_argument& e) {
    CHECK(std::string(e.what()).find("8 deformable points, fewer than the 9 ranks") !=
          std::string::npos);
  }
  CHECK_THROWS_AS(ckpd::decompose({&small}, {false}, 0), std::invalid_argument);
}

TEST_CASE("check --ranks prints each rank's points, work, halo and bytes", "[cli]") {
  using namespace ckpd::testing;
  const auto dir = fresh_dir("check_ranks");
  const std::string file = write_file(dir / "case.yaml", R"(# SI units
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.3}
bodies:
  - {name: bar, material: steel, geometry: {type: box, min: [0, 0, 0], max: [0.011, 0.003, 0.003]},
     spacing: 0.001, horizon_ratio: 2.015}
time: {steps: 10}
)");
  const CommandResult ok = run_ckpd("check " + file + " --steps 0 --ranks 3");
  INFO(ok.output);
  REQUIRE(ok.exit_code == 0);
  CHECK(ok.output.find("decomposition over 3 ranks") != std::string::npos);
  CHECK(ok.output.find("rank 2: ") != std::string::npos);
  CHECK(ok.output.find("halo points") != std::string::npos);
  // One deformable body without contact: the run would hold each rank's part only.
  CHECK(ok.output.find("distributed memory: each rank holds its points and their halo") !=
        std::string::npos);
  const CommandResult bad = run_ckpd("check " + file + " --steps 0 --ranks 1000");
  INFO(bad.output);
  CHECK(bad.exit_code == 2);
  CHECK(bad.output.find("fewer than the 1000 ranks") != std::string::npos);
}

TEST_CASE("check --ranks says which contact scenes distributed memory takes", "[cli]") {
  using namespace ckpd::testing;
  const auto dir = fresh_dir("check_ranks_contact");
  // Two bars in contact under the seed law, then under a DEM law with friction.
  const std::string bars = R"(# SI units
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.3}
bodies:
  - {name: a, material: steel, geometry: {type: box, min: [0, 0, 0], max: [0.011, 0.003, 0.003]},
     spacing: 0.001, horizon_ratio: 2.015}
  - {name: b, material: steel, geometry: {type: box, min: [0, 0, 0.0035], max: [0.011, 0.003, 0.0065]},
     spacing: 0.001, horizon_ratio: 2.015}
time: {steps: 10}
)";
  const std::string seed =
      write_file(dir / "seed.yaml", bars + "contact: {stiffness: 1.0e12, radius: 0.0008}\n");
  const CommandResult ok = run_ckpd("check " + seed + " --steps 0 --ranks 2");
  INFO(ok.output);
  REQUIRE(ok.exit_code == 0);
  CHECK(ok.output.find("distributed memory: each rank holds its points and their halo") !=
        std::string::npos);
  CHECK(ok.output.find("contact on distributed memory: each rank takes as contact ghosts") !=
        std::string::npos);
  // How the ranks would write the frames: together where this build's HDF5 is parallel.
  CHECK(ok.output.find(ckpd::hdf5::shared_files()
                           ? "field frames and checkpoints: written by every rank into shared files"
                           : "field frames and checkpoints: gathered to rank 0") !=
        std::string::npos);
  const std::string friction = write_file(
      dir / "friction.yaml",
      bars +
          "contact: {stiffness: 1.0e12, radius: 0.0008, law: linear_dashpot, restitution: 0.5, "
          "friction: 0.3}\n");
  const CommandResult replicated = run_ckpd("check " + friction + " --steps 0 --ranks 2");
  INFO(replicated.output);
  REQUIRE(replicated.exit_code == 0);
  CHECK(replicated.output.find("replicated state") != std::string::npos);
  CHECK(replicated.output.find("has friction") != std::string::npos);
}
