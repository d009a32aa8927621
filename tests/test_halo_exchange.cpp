// The halo exchange over time (src/engine/halo_exchange.hpp, issue 14): three "ranks" in one
// process, each holding only its restriction (owned points and halo), step a stretched, damaged
// block with velocity Verlet for 200 steps, exchanging ghost state forward and ghost forces back
// (the messages copied from one rank's send buffer to the other's receive buffer, as MPI would
// carry them; tests/mpi/halo_exchange_mpi.cpp runs the same under mpirun). Against the replicated
// scheme of today's MPI runs (every rank the whole body, partial forces summed in rank order) the
// owned points' displacements and velocities are the same bits at one thread, bond for bond the
// same failures; against the single-process run within 1e-12 of the largest displacement, at 1
// and 2 threads, 2D and 3D.
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

using namespace halo_fixtures;

namespace {

constexpr int kRanks = 3;

struct Rank {
  ckpd::HaloLinks links;
  ckpd::BodyRestriction part;
  ckpd::HaloBuffers buffers;
};

// What MPI carries: rank r's receive buffer from q is q's send buffer to r.
void deliver(std::vector<Rank>& ranks) {
  for (std::size_t r = 0; r < ranks.size(); ++r)
    for (std::size_t q = 0; q < ranks.size(); ++q)
      if (q != r) {
        const std::vector<double>& sent = ranks[q].buffers.send[r];
        REQUIRE(sent.size() == ranks[r].buffers.receive[q].size());
        ranks[r].buffers.receive[q] = sent;
      }
}

void exchange_state(std::vector<Rank>& ranks) {
  for (Rank& k : ranks) ckpd::pack_state(k.links, k.part.body, k.buffers);
  deliver(ranks);
  for (Rank& k : ranks) ckpd::unpack_state(k.links, k.buffers, k.part.body);
}

void distributed_forces(std::vector<Rank>& ranks) {
  for (Rank& k : ranks) {
    ckpd::compute_internal_force_symmetric(k.part.body, false);
    ckpd::pack_ghost_forces(k.links, k.part.body, false, k.buffers);
  }
  deliver(ranks);
  for (std::size_t r = 0; r < ranks.size(); ++r)
    ckpd::add_owner_forces(ranks[r].links, static_cast<int>(r), ranks[r].buffers, false,
                           ranks[r].part.body);
}

}  // namespace

TEST_CASE("ranks holding only their halo step a fracturing body as the replicated ranks do",
          "[halo_exchange]") {
  kernel_comparison::ThreadCountGuard guard;
  for (const int dimension : {2, 3})
    for (const int threads : {1, 2}) {
      INFO(dimension << "D, " << threads << " thread(s)");
      omp_set_num_threads(threads);
      std::mt19937 rng(11);
      Body whole = pulled_block(dimension, rng);
      Body replicated = whole;
      const std::vector<int> owner = ckpd::decompose({&whole}, {false}, kRanks).owner[0];
      std::vector<Rank> ranks(kRanks);
      for (int r = 0; r < kRanks; ++r) {
        Rank& k = ranks[static_cast<std::size_t>(r)];
        k.links = ckpd::halo_links(whole, owner, r, kRanks);
        k.part = ckpd::restrict_body(whole, k.links.points);
        k.part.body.owned_centres = k.links.owned;
      }
      const double dt = 0.5 * ckpd::stable_step(whole).dt;
      ckpd::compute_internal_force_symmetric(whole, false);
      replicated_forces(replicated, owner, kRanks);
      distributed_forces(ranks);
      for (int step = 0; step < kSteps; ++step) {
        for (Body* b : {&whole, &replicated}) {
          kick(*b, dt / 2);
          drift(*b, dt);
          ckpd::fail_overstretched_bonds(*b, dt / 2);
        }
        for (Rank& k : ranks) {
          kick(k.part.body, dt / 2, &k.links.owned);
          drift(k.part.body, dt, &k.links.owned);
        }
        exchange_state(ranks);
        for (Rank& k : ranks) ckpd::fail_overstretched_bonds(k.part.body, dt / 2);
        ckpd::compute_internal_force_symmetric(whole, false);
        replicated_forces(replicated, owner, kRanks);
        distributed_forces(ranks);
        kick(whole, dt / 2);
        kick(replicated, dt / 2);
        for (Rank& k : ranks) kick(k.part.body, dt / 2, &k.links.owned);
      }
      std::size_t broken = 0;
      for (const std::uint8_t intact : whole.bond_intact) broken += intact == 0;
      INFO("broken bond entries in the whole body's run: " << broken);
      CHECK(broken > 0);
      const double scale = kernel_comparison::max_norm(whole.displacement);
      for (const Rank& k : ranks) {
        const Agreement a = compare(k.part.body, k.part.global, k.links.owned, whole, replicated);
        INFO("owned points not bitwise equal to the replicated run: "
             << a.not_bitwise << "; largest displacement difference from the single process: "
             << a.displacement / scale << " of the largest displacement");
        if (threads == 1) CHECK(a.not_bitwise == 0);
        CHECK(a.failures_differ == 0);
        CHECK(a.displacement <= 1e-12 * scale);
      }
    }
}
