// The halo exchange's links (src/engine/halo.hpp): a rank keeps its own points and their family
// members, receives each ghost from its owner once, and rank r's send list to q names the points
// of q's receive list from r in the same order; the ghost counts are the decomposition's. With
// the partial forces of each rank's restriction sent back along the links and added in rank
// order at the owners, every point gets the replicated scheme's sum (force_sharing.hpp) bit for
// bit at one thread and the whole body's force to 1e-12 at two: the halo exchange computes what
// today's MPI runs compute.
#include <omp.h>

#include <catch2/catch.hpp>
#include <random>
#include <stdexcept>
#include <vector>

#include "bodies/sub_body.hpp"
#include "bodies/symmetric_kernel.hpp"
#include "kernel_comparison.hpp"
#include "src/engine/decomposition.hpp"
#include "src/engine/halo.hpp"

using namespace kernel_comparison;

namespace {

Body damaged_block(int dimension, bool stencil, std::mt19937& rng) {
  const Scene s{"block",
                dimension,
                dimension == 3 ? 0.3 : 0.4,
                0.0,
                dimension == 3 ? 9 : 18,
                dimension == 3 ? 6 : 12,
                dimension == 3 ? 5 : 1};
  BodyDefinition d = block(s.dimension, s.nx, s.ny, s.nz, constants_for(s), 0.0, rng);
  d.lattice_stencil = stencil;
  Body body = ckpd::make_body(d);
  perturb(body, 0.05, rng);
  fail_bonds(body, 0.15, rng);
  return body;
}

std::vector<int> random_owners(std::size_t n, int ranks, std::mt19937& rng) {
  std::uniform_int_distribution<int> pick(0, ranks - 1);
  std::vector<int> owner(n);
  for (int& o : owner) o = pick(rng);
  return owner;
}

}  // namespace

TEST_CASE("halo links receive each ghost once and match the owners' send lists", "[halo]") {
  std::mt19937 rng(31);
  const Body body = damaged_block(3, true, rng);
  for (const bool random : {false, true})
    for (const int ranks : {2, 3, 4}) {
      const std::vector<int> owner = random ? random_owners(body.size(), ranks, rng)
                                            : ckpd::decompose({&body}, {false}, ranks).owner[0];
      std::vector<ckpd::HaloLinks> links;
      for (int r = 0; r < ranks; ++r) links.push_back(ckpd::halo_links(body, owner, r, ranks));
      for (int r = 0; r < ranks; ++r) {
        const ckpd::HaloLinks& l = links[static_cast<std::size_t>(r)];
        std::vector<std::uint8_t> core(body.size());
        for (std::size_t i = 0; i < body.size(); ++i) core[i] = owner[i] == r;
        CHECK(l.points == ckpd::core_and_halo(body, core));
        std::vector<int> received(l.points.size(), 0);
        for (int q = 0; q < ranks; ++q) {
          const auto& in = l.receive[static_cast<std::size_t>(q)];
          const auto& out = links[static_cast<std::size_t>(q)].send[static_cast<std::size_t>(r)];
          REQUIRE(in.size() == out.size());
          for (std::size_t k = 0; k < in.size(); ++k) {
            ++received[in[k]];
            CHECK(owner[l.points[in[k]]] == q);
            // The same point, at the same place in the message.
            CHECK(l.points[in[k]] == links[static_cast<std::size_t>(q)].points[out[k]]);
          }
        }
        for (std::size_t k = 0; k < l.points.size(); ++k)
          CHECK(received[k] == (l.owned[k] ? 0 : 1));
        if (!random) {
          const ckpd::Decomposition d = ckpd::decompose({&body}, {false}, ranks);
          CHECK(l.ghosts() == d.share[static_cast<std::size_t>(r)].ghosts);
        }
      }
    }
}

TEST_CASE("forces sent back along the halo links equal the replicated ranks' sum", "[halo]") {
  ThreadCountGuard guard;
  for (const int dimension : {2, 3})
    for (const bool stencil : {true, false})
      for (const bool random : {false, true}) {
        std::mt19937 rng(77);
        Body body = damaged_block(dimension, stencil, rng);
        const int ranks = 3;
        const std::vector<int> owner = random ? random_owners(body.size(), ranks, rng)
                                              : ckpd::decompose({&body}, {false}, ranks).owner[0];
        INFO(dimension << "D, " << (stencil ? "stencil" : "general") << ", "
                       << (random ? "random owners" : "bisection"));
        // The replicated scheme at one thread: every rank's partial buffer over the whole body,
        // summed in rank order for every point.
        omp_set_num_threads(1);
        std::vector<Vec3> replicated(body.size(), Vec3::Zero());
        for (int r = 0; r < ranks; ++r) {
          body.owned_centres.assign(body.size(), 0);
          for (std::size_t i = 0; i < body.size(); ++i) body.owned_centres[i] = owner[i] == r;
          ckpd::compute_internal_force_symmetric(body, false);
          for (std::size_t i = 0; i < body.size(); ++i) replicated[i] += body.force_density[i];
        }
        body.owned_centres.clear();
        ckpd::compute_internal_force_symmetric(body, false);
        const std::vector<Vec3> whole = body.force_density;
        for (const int threads : {1, 2}) {
          omp_set_num_threads(threads);
          std::vector<ckpd::HaloLinks> links;
          std::vector<ckpd::BodyRestriction> parts;
          for (int r = 0; r < ranks; ++r) {
            links.push_back(ckpd::halo_links(body, owner, r, ranks));
            parts.push_back(ckpd::restrict_body(body, links.back().points));
            parts.back().body.owned_centres = links.back().owned;
            ckpd::compute_internal_force_symmetric(parts.back().body, false);
          }
          // At each owner: the partials in rank order, its own at its place, each other rank's
          // from the message that rank sends it (its receive list from the owner, in order).
          std::vector<Vec3> total(body.size(), Vec3::Constant(1e300));
          for (int r = 0; r < ranks; ++r) {
            const std::size_t R = static_cast<std::size_t>(r);
            std::vector<Vec3> sum(parts[R].global.size(), Vec3::Zero());
            for (int q = 0; q < ranks; ++q) {
              const std::size_t Q = static_cast<std::size_t>(q);
              if (q == r) {
                for (std::size_t k = 0; k < sum.size(); ++k)
                  if (links[R].owned[k]) sum[k] += parts[R].body.force_density[k];
                continue;
              }
              const auto& message = links[Q].receive[R];  // q's ghosts that r owns
              const auto& place = links[R].send[Q];       // the same points on r
              for (std::size_t k = 0; k < message.size(); ++k)
                sum[place[k]] += parts[Q].body.force_density[message[k]];
            }
            for (std::size_t k = 0; k < sum.size(); ++k)
              if (links[R].owned[k]) total[parts[R].global[k]] = sum[k];
          }
          std::size_t differing = 0;
          double err = 0;
          for (std::size_t i = 0; i < body.size(); ++i) {
            differing += total[i] != replicated[i];
            err = std::max(err, (total[i] - whole[i]).norm());
          }
          INFO(threads << " thread(s): " << differing << " points differ from the replicated sum, "
                       << "largest difference from the whole body " << err / max_norm(whole));
          if (threads == 1) CHECK(differing == 0);
          CHECK(err <= 1e-12 * max_norm(whole));
        }
      }
}

TEST_CASE("halo_links rejects owners that do not fit the body or the ranks", "[halo]") {
  std::mt19937 rng(3);
  const Body body = damaged_block(2, false, rng);
  std::vector<int> owner(body.size(), 0);
  CHECK_THROWS_AS(ckpd::halo_links(body, std::vector<int>(3, 0), 0, 2), std::invalid_argument);
  CHECK_THROWS_AS(ckpd::halo_links(body, owner, 2, 2), std::invalid_argument);
  owner[5] = 2;
  CHECK_THROWS_AS(ckpd::halo_links(body, owner, 0, 2), std::invalid_argument);
}
