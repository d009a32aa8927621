// Time per step of a case under the two MPI schemes (issue 14, docs/SCALING.md): `distributed`
// (each rank holds its restrictions, halo messages: src/engine/distribution.hpp) or `replicated`
// (every rank the whole scene, the partial force buffers summed: src/engine/force_sharing.hpp);
// with one rank both are the single-process run. Prints, from rank 0, the set-up time, the
// median step time of the timed steps (after one warm-up step), the largest peak RSS over ranks,
// and for the distributed scheme the ghosts and bytes per step of the largest rank.
//
//   mpirun -np 2 -x OMP_NUM_THREADS=1 build/bench/distributed_steps CASE distributed STEPS
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "src/case/case_loader.hpp"
#include "src/engine/distribution.hpp"
#include "src/engine/force_sharing.hpp"
#include "src/engine/ranks.hpp"
#include "src/engine/simulation.hpp"
#include "src/output/run_output.hpp"

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  ckpd::ranks::Session session(&argc, &argv);
  if (argc != 4) {
    std::fprintf(stderr, "usage: distributed_steps CASE distributed|replicated STEPS\n");
    return 2;
  }
  const std::string case_file = argv[1], scheme = argv[2];
  const int steps = std::atoi(argv[3]);
  const int rank = ckpd::ranks::rank(), ranks = ckpd::ranks::count();
  const auto start = std::chrono::steady_clock::now();
  ckpd::Scene whole = ckpd::load_scene(case_file);
  ckpd::DistributedScene part;
  std::unique_ptr<ckpd::Simulation> sim;
  double ghost_bytes = 0, ghosts = 0;
  if (scheme == "distributed") {
    part = ckpd::distribute_scene(whole, rank, ranks);
    for (std::size_t b = 0; b < part.distribution->body_count(); ++b) {
      const ckpd::HaloLinks& links = part.distribution->body(b).links;
      ghosts += static_cast<double>(links.ghosts());
      // forward: displacement and velocity of each point sent; backward: 3 forces per ghost
      ghost_bytes += static_cast<double>(links.sent() * ckpd::kStateValues * sizeof(double) +
                                         links.ghosts() * 3 * sizeof(double));
    }
    if (rank != 0)
      for (ckpd::SceneBody& sb : whole.bodies) sb.body = ckpd::Body();  // rank 0 keeps it
    sim = std::make_unique<ckpd::Simulation>(part.local, std::move(part.distribution));
  } else if (scheme == "replicated") {
    ckpd::share_force_work(whole, rank, ranks);
    sim = std::make_unique<ckpd::Simulation>(whole);
  } else {
    std::fprintf(stderr, "scheme: distributed or replicated\n");
    return 2;
  }
  const double set_up = seconds_since(start);
  sim->advance(false);  // warm-up: workspaces, first messages
  std::vector<double> times;
  for (int s = 0; s < steps; ++s) {
    const auto t = std::chrono::steady_clock::now();
    sim->advance(false);
    std::vector<double> mine{seconds_since(t)}, all;
    ckpd::ranks::all_gather(mine, all);  // a step takes as long as its slowest rank
    times.push_back(*std::max_element(all.begin(), all.end()));
  }
  std::sort(times.begin(), times.end());
  std::vector<double> mine{ckpd::peak_rss_mb(), ghosts, ghost_bytes}, all;
  ckpd::ranks::all_gather(mine, all);
  double rss = 0, most_ghosts = 0, most_bytes = 0;
  for (std::size_t r = 0; r * 3 < all.size(); ++r) {
    rss = std::max(rss, all[r * 3]);
    most_ghosts = std::max(most_ghosts, all[r * 3 + 1]);
    most_bytes = std::max(most_bytes, all[r * 3 + 2]);
  }
  if (rank == 0)
    std::printf(
        "%s ranks %d: set-up %.2f s, step median %.4f s (min %.4f, max %.4f) over %d steps, "
        "peak RSS %.1f MB (largest rank), ghosts %.0f, bytes sent per step %.0f (largest rank)\n",
        scheme.c_str(), ranks, set_up, times[times.size() / 2], times.front(), times.back(), steps,
        rss, most_ghosts, most_bytes);
  return 0;
}
