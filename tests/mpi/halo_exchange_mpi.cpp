// The halo exchange under mpirun (issue 14): each rank holds only its restriction of a block
// pulled apart until it fractures (tests/halo_fixtures.hpp), and the ghosts' state and the ghost
// forces travel through ranks::exchange (MPI point to point) for 200 velocity-Verlet steps. Each
// rank also runs the single-process and the replicated schemes on the whole body by itself and
// checks its owned points against them: the replicated run's bits (one thread per rank), the
// single-process run to 1e-12 of the largest displacement, every bond it holds with the same
// flag. Run by ctest at 2 and 3 ranks (tests/CMakeLists.txt).
#define CATCH_CONFIG_RUNNER
#include <omp.h>

#include <catch2/catch.hpp>
#include <random>
#include <vector>

#include "bodies/damage.hpp"
#include "bodies/sub_body.hpp"
#include "halo_fixtures.hpp"
#include "src/engine/decomposition.hpp"
#include "src/engine/halo.hpp"
#include "src/engine/halo_exchange.hpp"
#include "src/engine/ranks.hpp"

using namespace halo_fixtures;

TEST_CASE("ranks holding only their halo step a fracturing body over MPI as one process does",
          "[halo_exchange_mpi]") {
  const int rank = ckpd::ranks::rank(), ranks = ckpd::ranks::count();
  REQUIRE(ranks >= 2);
  for (const int dimension : {2, 3}) {
    INFO(dimension << "D, rank " << rank << " of " << ranks);
    std::mt19937 rng(11);
    Body whole = pulled_block(dimension, rng);  // the same body on every rank
    Body replicated = whole;
    const std::vector<int> owner = ckpd::decompose({&whole}, {false}, ranks).owner[0];
    const ckpd::HaloLinks links = ckpd::halo_links(whole, owner, rank, ranks);
    ckpd::BodyRestriction part = ckpd::restrict_body(whole, links.points);
    Body& mine = part.body;
    mine.owned_centres = links.owned;
    ckpd::HaloBuffers buffers;
    auto distributed_forces = [&] {
      ckpd::compute_internal_force_symmetric(mine, false);
      ckpd::pack_ghost_forces(links, mine, false, buffers);
      ckpd::ranks::exchange(buffers.send, buffers.receive);
      ckpd::add_owner_forces(links, rank, buffers, false, mine);
    };
    const double dt = 0.5 * ckpd::stable_step(whole).dt;
    ckpd::compute_internal_force_symmetric(whole, false);
    replicated_forces(replicated, owner, ranks);
    distributed_forces();
    for (int step = 0; step < kSteps; ++step) {
      for (Body* b : {&whole, &replicated}) {
        kick(*b, dt / 2);
        drift(*b, dt);
        ckpd::fail_overstretched_bonds(*b, dt / 2);
      }
      kick(mine, dt / 2, &links.owned);
      drift(mine, dt, &links.owned);
      ckpd::pack_state(links, mine, buffers);
      ckpd::ranks::exchange(buffers.send, buffers.receive);
      ckpd::unpack_state(links, buffers, mine);
      ckpd::fail_overstretched_bonds(mine, dt / 2);
      ckpd::compute_internal_force_symmetric(whole, false);
      replicated_forces(replicated, owner, ranks);
      distributed_forces();
      kick(whole, dt / 2);
      kick(replicated, dt / 2);
      kick(mine, dt / 2, &links.owned);
    }
    std::size_t broken = 0;
    for (const std::uint8_t intact : whole.bond_intact) broken += intact == 0;
    CHECK(broken > 0);
    CHECK(links.ghosts() > 0);
    const double scale = kernel_comparison::max_norm(whole.displacement);
    const Agreement a = compare(mine, part.global, links.owned, whole, replicated);
    INFO("owned points not bitwise equal to the replicated run: "
         << a.not_bitwise << "; largest displacement difference from the single process: "
         << a.displacement / scale << "; ghosts " << links.ghosts());
    CHECK(a.not_bitwise == 0);
    CHECK(a.failures_differ == 0);
    CHECK(a.displacement <= 1e-12 * scale);
  }
}

int main(int argc, char** argv) {
  ckpd::ranks::Session session(&argc, &argv);
  omp_set_num_threads(1);  // the replicated run's bits are those of one thread per rank
  return Catch::Session().run(argc, argv);
}
