// The halo exchange over time (src/engine/halo_exchange.hpp, issue 14): three "ranks" in one
// process, each holding only its restriction (owned points and halo), step a stretched, damaged
// block with velocity Verlet for 200 steps, exchanging ghost state forward and ghost forces back
// (the messages copied from one rank's send buffer to the other's receive buffer, as MPI would
// carry them). Against the replicated scheme of today's MPI runs (every rank the whole body,
// partial forces summed in rank order) the owned points' displacements and velocities are the
// same bits at one thread, bond for bond the same failures; against the single-process run
// within 1e-12 of the largest displacement, at 1 and 2 threads, 2D and 3D.
#include <omp.h>

#include <catch2/catch.hpp>
#include <random>
#include <vector>

#include "bodies/damage.hpp"
#include "bodies/sub_body.hpp"
#include "bodies/symmetric_kernel.hpp"
#include "kernel_comparison.hpp"
#include "src/engine/decomposition.hpp"
#include "src/engine/halo.hpp"
#include "src/engine/halo_exchange.hpp"

using namespace kernel_comparison;

namespace {

constexpr int kRanks = 3;
constexpr int kSteps = 200;  // the MPI tests' length (tests/mpi/)

// A block pulled apart from its middle (velocity proportional to x - centre), small random
// displacements, a critical stretch that the pull exceeds within the run.
Body pulled_block(int dimension, std::mt19937& rng) {
  // m = 2.015 in 3D keeps the test fast (a tenth of the tetrahedra of m = 3).
  const double m = dimension == 3 ? 2.015 : kM;
  const Scene s{"block",
                dimension,
                dimension == 3 ? 0.3 : 0.4,
                0.0,
                dimension == 3 ? 10 : 20,
                dimension == 3 ? 5 : 10,
                dimension == 3 ? 5 : 1,
                false,
                m};
  BodyDefinition d = block(s.dimension, s.nx, s.ny, s.nz, constants_for(s), 0.0, rng, m);
  d.critical_stretch = 4e-3;
  Body body = ckpd::make_body(d);
  perturb(body, 1e-4, rng);
  double lo = 1e300, hi = -1e300;
  for (const Vec3& p : body.reference_position) {
    lo = std::min(lo, p.x());
    hi = std::max(hi, p.x());
  }
  for (std::size_t i = 0; i < body.size(); ++i) {
    const double t = (body.reference_position[i].x() - 0.5 * (lo + hi)) / (hi - lo);
    body.velocity[i] = Vec3(100.0 * t, 0, 0);  // m/s
  }
  return body;
}

// Kick and drift of the points with move[i] != 0 (all: null).
void kick(Body& body, double h, const std::vector<std::uint8_t>* move) {
  for (std::size_t i = 0; i < body.size(); ++i)
    if (move == nullptr || (*move)[i]) body.velocity[i] += h * body.force_density[i] / body.density;
}
void drift(Body& body, double dt, const std::vector<std::uint8_t>* move) {
  for (std::size_t i = 0; i < body.size(); ++i)
    if (move == nullptr || (*move)[i]) body.displacement[i] += dt * body.velocity[i];
}

// The replicated scheme's forces: each rank's centres on the whole body, summed in rank order.
void replicated_forces(Body& body, const std::vector<int>& owner) {
  std::vector<Vec3> sum(body.size(), Vec3::Zero());
  for (int r = 0; r < kRanks; ++r) {
    body.owned_centres.assign(body.size(), 0);
    for (std::size_t i = 0; i < body.size(); ++i) body.owned_centres[i] = owner[i] == r;
    ckpd::compute_internal_force_symmetric(body, false);
    for (std::size_t i = 0; i < body.size(); ++i) sum[i] += body.force_density[i];
  }
  body.force_density = sum;
}

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
  ThreadCountGuard guard;
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
      replicated_forces(replicated, owner);
      distributed_forces(ranks);
      for (int step = 0; step < kSteps; ++step) {
        for (Body* b : {&whole, &replicated}) {
          kick(*b, dt / 2, nullptr);
          drift(*b, dt, nullptr);
          ckpd::fail_overstretched_bonds(*b, dt / 2);
        }
        for (Rank& k : ranks) {
          kick(k.part.body, dt / 2, &k.links.owned);
          drift(k.part.body, dt, &k.links.owned);
        }
        exchange_state(ranks);
        for (Rank& k : ranks) ckpd::fail_overstretched_bonds(k.part.body, dt / 2);
        ckpd::compute_internal_force_symmetric(whole, false);
        replicated_forces(replicated, owner);
        distributed_forces(ranks);
        kick(whole, dt / 2, nullptr);
        kick(replicated, dt / 2, nullptr);
        for (Rank& k : ranks) kick(k.part.body, dt / 2, &k.links.owned);
      }
      std::size_t broken = 0;
      for (const std::uint8_t intact : whole.bond_intact) broken += intact == 0;
      INFO("broken bond entries in the whole body's run: "
           << broken << ", dt " << dt << ", largest displacement " << max_norm(whole.displacement));
      CHECK(broken > 0);
      const double scale = max_norm(whole.displacement);
      std::size_t not_bitwise = 0, failures_differ = 0;
      double err = 0;
      for (const Rank& k : ranks) {
        const Body& b = k.part.body;
        for (std::size_t l = 0; l < b.size(); ++l) {
          const std::size_t g = k.part.global[l];
          if (k.links.owned[l]) {
            not_bitwise += b.displacement[l] != replicated.displacement[g] ||
                           b.velocity[l] != replicated.velocity[g];
            err = std::max(err, (b.displacement[l] - whole.displacement[g]).norm());
          }
          // Every bond a rank holds has the whole run's flag.
          std::size_t e = whole.family.offset[g];
          for (std::size_t m = b.family.offset[l]; m < b.family.offset[l + 1]; ++m) {
            while (whole.family.neighbour[e] != k.part.global[b.family.neighbour[m]]) ++e;
            failures_differ += b.bond_intact[m] != whole.bond_intact[e];
          }
        }
      }
      INFO("owned points not bitwise equal to the replicated run: "
           << not_bitwise << "; largest displacement difference from the single process: "
           << err / scale << " of the largest displacement");
      if (threads == 1) CHECK(not_bitwise == 0);
      CHECK(failures_differ == 0);
      CHECK(err <= 1e-12 * scale);
    }
}
