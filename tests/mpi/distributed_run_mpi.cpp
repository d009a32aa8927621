// Distributed memory under mpirun (issue 14, src/engine/distribution.hpp): each rank holds only
// its restrictions of the bodies of tests/mpi/pulled_bars.yaml (a bar pulled apart until it
// breaks, a spinning bead flying beside it) and the Simulation steps them with the halo exchange.
// Against the single-process run of the same case, which every rank also makes by itself: the
// energies and counts of every history row (summed over ranks) within 1e-12, and at the end,
// gathered on rank 0, every point's displacement within 1e-12 of the largest, every bond's flag,
// the fragments. An unstable run stops every rank with the single-process run's message (the
// point named by its index in the whole body). Run by ctest at 2 and 3 ranks.
#define CATCH_CONFIG_RUNNER
#include <omp.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "bodies/fragments.hpp"
#include "src/case/case_loader.hpp"
#include "src/engine/distribution.hpp"
#include "src/engine/ranks.hpp"
#include "src/engine/simulation.hpp"

namespace {

const std::string kCase = std::string(CKPD_SOURCE_DIR) + "/tests/mpi/pulled_bars.yaml";

bool close(double a, double b, double scale) {
  return std::abs(a - b) <= 1e-12 * std::max({std::abs(a), std::abs(b), scale});
}

}  // namespace

TEST_CASE("a distributed run of a breaking bar and a flying bead is the single-process run",
          "[distributed_mpi]") {
  const int rank = ckpd::ranks::rank(), ranks = ckpd::ranks::count();
  REQUIRE(ranks >= 2);
  INFO("rank " << rank << " of " << ranks);
  ckpd::Scene single_scene = ckpd::load_scene(kCase);
  ckpd::Simulation single(single_scene);
  ckpd::Scene whole = ckpd::load_scene(kCase);
  ckpd::DistributedScene part = ckpd::distribute_scene(whole, rank, ranks);
  ckpd::Simulation run(part.local, std::move(part.distribution));
  REQUIRE(run.step_choice().dt == single.step_choice().dt);
  std::size_t rows = 0;
  while (single.step() < single.planned_steps()) {
    const bool row = (single.step() + 1) % 20 == 0;
    single.advance(row);
    run.advance(row);
    if (!row) continue;
    ++rows;
    const ckpd::Energies a = single.energies(), b = run.energies();
    INFO("step " << single.step());
    const double scale = a.kinetic + a.external_work;
    CHECK(close(a.kinetic, b.kinetic, scale));
    CHECK(close(a.strain, b.strain, scale));
    CHECK(close(a.external_work, b.external_work, scale));
    CHECK(close(a.dissipated, b.dissipated, scale));
    CHECK(single.broken_bonds() == run.broken_bonds());
    CHECK(close(single.max_damage(), run.max_damage(), 1));
    // The kernels' work, each set once over the ranks: the single run's counts.
    for (std::size_t k = 0; k < single_scene.bodies.size(); ++k) {
      CHECK(single.evaluated(k).bonds == run.evaluated(k).bonds);
      CHECK(single.evaluated(k).triangles == run.evaluated(k).triangles);
      CHECK(single.evaluated(k).tetrahedra == run.evaluated(k).tetrahedra);
    }
  }
  CHECK(rows == 12);
  INFO("broken bonds " << single.broken_bonds());
  CHECK(single.broken_bonds() > 100);  // the bar breaks

  run.distribution()->gather(part.local, whole);
  if (rank != 0) return;
  for (std::size_t k = 0; k < whole.bodies.size(); ++k) {
    const ckpd::Body& a = single_scene.bodies[k].body;
    const ckpd::Body& b = whole.bodies[k].body;
    INFO("body " << a.name);
    double largest = 0, differs = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
      largest = std::max(largest, a.displacement[i].norm());
      differs = std::max(differs, (a.displacement[i] - b.displacement[i]).norm());
    }
    INFO("largest displacement difference " << differs / largest << " of the largest");
    CHECK(differs <= 1e-12 * largest);
    CHECK(a.bond_intact == b.bond_intact);
    const ckpd::FragmentCensus fa = ckpd::find_fragments(a), fb = ckpd::find_fragments(b);
    CHECK(fa.label == fb.label);
    if (k == 0) CHECK(fa.count_at_least(10) >= 2);  // the bar broken
  }
}

TEST_CASE("an unstable distributed run stops every rank with the single-process run's message",
          "[distributed_mpi]") {
  const int rank = ckpd::ranks::rank(), ranks = ckpd::ranks::count();
  // Seven times the stable step with an energy evaluation every 20 steps: the energy guard stops
  // the run; thirty times, unbreakable, without energy: the speed guard.
  for (const auto& [dt, row_interval] : {std::pair<const char*, int>{"1e-6", 20}, {"4e-6", 0}}) {
    INFO("rank " << rank << " of " << ranks << ", dt " << dt);
    std::vector<std::string> unstable{std::string("time.dt=") + dt, "time.allow_unstable_dt=true",
                                      "time.steps=2000"};
    if (row_interval == 0) unstable.push_back("materials.glass.fracture_energy=1e12");
    auto message_of = [&](ckpd::Simulation& sim) {
      try {
        while (sim.step() < sim.planned_steps())
          sim.advance(row_interval > 0 && (sim.step() + 1) % row_interval == 0);
      } catch (const ckpd::InstabilityError& e) {
        return std::string(e.what());
      }
      return std::string();
    };
    ckpd::Scene single_scene = ckpd::load_scene(kCase, unstable);
    ckpd::Simulation single(single_scene);
    const std::string expected = message_of(single);
    INFO("single process: " << expected);
    REQUIRE(!expected.empty());
    CHECK(expected.find(row_interval > 0 ? "energy" : "moves at") != std::string::npos);
    ckpd::Scene whole = ckpd::load_scene(kCase, unstable);
    ckpd::DistributedScene part = ckpd::distribute_scene(whole, rank, ranks);
    ckpd::Simulation run(part.local, std::move(part.distribution));
    CHECK(message_of(run) == expected);
  }
}

int main(int argc, char** argv) {
  ckpd::ranks::Session session(&argc, &argv);
  omp_set_num_threads(1);
  return Catch::Session().run(argc, argv);
}
