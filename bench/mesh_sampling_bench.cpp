// Mesh sampling benchmark: loads a mesh file (scripts/generate_meshes.py torus ...), samples it
// on a cubic lattice of spacing dx several times and prints the median time of the load
// (assimp + weld + checks) and of the sampling, the point count and the peak RSS.
//
//   mesh_sampling_bench MESH DX [REPEATS]
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "src/geometry/lattice.hpp"
#include "src/geometry/mesh/mesh_shape.hpp"

using namespace ckpd;

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s MESH DX [REPEATS]\n", argv[0]);
    return 2;
  }
  const std::string file = argv[1];
  const double dx = std::atof(argv[2]);
  const int repeats = argc > 3 ? std::atoi(argv[3]) : 5;
  std::vector<double> load, sample;
  std::size_t points = 0, triangles = 0;
  double volume = 0, mesh_volume = 0;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    const YAML::Node node = YAML::Load("{type: mesh, file: '" + file + "'}");
    const auto shape = make_shape(CaseNode(node, "bench.yaml"), 3);
    const auto t1 = std::chrono::steady_clock::now();
    const LatticeSample s = sample_lattice(*shape, 3, dx, 3 * dx, 100'000'000);
    const auto t2 = std::chrono::steady_clock::now();
    load.push_back(std::chrono::duration<double>(t1 - t0).count());
    sample.push_back(std::chrono::duration<double>(t2 - t1).count());
    const auto& info = static_cast<const MeshShape&>(*shape).info();
    triangles = info.triangles;
    mesh_volume = info.mesh_volume;
    points = s.position.size();
    volume = 0;
    for (double v : s.volume) volume += v;
  }
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  std::printf("mesh %s: %zu triangles, volume %.6g m^3; dx %.6g m\n", file.c_str(), triangles,
              mesh_volume, dx);
  std::printf("points %zu, sampled volume %.6g m^3 (%+.3f %%)\n", points, volume,
              100 * (volume / mesh_volume - 1));
  std::printf("median of %d: load %.3f s, sampling %.3f s; peak RSS %.1f MB\n", repeats,
              median(load), median(sample), usage.ru_maxrss / 1024.0);
  return 0;
}
