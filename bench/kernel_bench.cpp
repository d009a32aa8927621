// Times the reference internal-force kernel (compute_internal_force: every point walks its own
// family, so each tetrahedron is evaluated four times) against the once-per-interaction kernel
// (compute_internal_force_symmetric) on a lattice block (3D by default; --dim 2 for a plane
// stress square, where the triangles do the work), at 1 and 2 OpenMP threads.
//
//   kernel_bench [--dim 3] [--n 24] [--m 3.015] [--nu 0.3] [--reps 7] [--ref-reps 3]
//                [--threads 1,2] [--energy] [--jitter 0] [--order lex|morton] [--strain-measure
//                0.5] [--bonds-only]
// --jitter j moves every point by up to +-j dx per component: an irregular cloud, whose slivers
// (nearly flat tetrahedra) the fast kernel evaluates vertex by vertex. --order morton numbers
// the points along a Morton curve (a space-filling-curve ordering; no lattice stencil then).
// --bonds-only sets C2 = C3 = 0 (a bond-only body: the bond-only kernel, bodies/symmetric/
// bond_only.hpp) and times it against the general path of the same kernel (the body without its
// bond table), alternately, in bonds per second.
//
// Prints the setup, the median (and min/max) milliseconds per evaluation, interactions per
// second, the speed-up of the fast kernel and its thread scaling, and the largest difference
// between the two kernels relative to the largest force.
#include <omp.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "bodies/body.hpp"
#include "bodies/lattice_stencil.hpp"
#include "bodies/material.hpp"
#include "bodies/symmetric_kernel.hpp"
#include "reference/internal_force.hpp"

namespace {

using ckpd::Vec3;

struct Options {
  int dim = 3;
  int n = 24;
  double m = 3.015;
  double nu = 0.3;
  int reps = 7;
  int ref_reps = 3;
  std::vector<int> threads{1, 2};
  bool energy = false;
  double jitter = 0;
  bool morton = false;  // number the points along a Morton (Z-order) curve instead of (z, y, x)
  double strain_measure = 0.5;  // Seth-Hill m (1/2: the default linear law)
  bool bonds_only = false;      // C2 = C3 = 0
};

Options parse(int argc, char** argv) {
  Options o;
  for (int a = 1; a < argc; ++a) {
    const std::string key = argv[a];
    auto value = [&]() -> std::string {
      if (a + 1 >= argc) throw std::invalid_argument(key + " needs a value");
      return argv[++a];
    };
    if (key == "--dim") {
      o.dim = std::stoi(value());
      if (o.dim != 2 && o.dim != 3) throw std::invalid_argument("--dim is 2 or 3");
    } else if (key == "--n") {
      o.n = std::stoi(value());
    } else if (key == "--m") {
      o.m = std::stod(value());
    } else if (key == "--nu") {
      o.nu = std::stod(value());
    } else if (key == "--reps") {
      o.reps = std::stoi(value());
    } else if (key == "--ref-reps") {
      o.ref_reps = std::stoi(value());
    } else if (key == "--threads") {
      o.threads.clear();
      std::stringstream list(value());
      for (std::string item; std::getline(list, item, ',');) o.threads.push_back(std::stoi(item));
    } else if (key == "--jitter") {
      o.jitter = std::stod(value());
    } else if (key == "--energy") {
      o.energy = true;
    } else if (key == "--bonds-only") {
      o.bonds_only = true;
    } else if (key == "--strain-measure") {
      o.strain_measure = std::stod(value());
    } else if (key == "--order") {
      const std::string order = value();
      if (order != "lex" && order != "morton") throw std::invalid_argument("--order lex|morton");
      o.morton = order == "morton";
    } else {
      throw std::invalid_argument("unknown option " + key);
    }
  }
  return o;
}

ckpd::Body lattice_body(const Options& o) {
  const double dx = 1e-3, E = 210e9;
  ckpd::BodyDefinition d;
  d.name = "bench block";
  d.dimension = o.dim;
  d.density = 7850;
  d.horizon = o.m * dx;
  d.constants = ckpd::interaction_constants(
      o.dim, E, o.nu, o.dim == 3 ? ckpd::PlaneMode::none : ckpd::PlaneMode::stress, d.horizon);
  if (o.bonds_only) d.constants.c2 = d.constants.c3 = 0;
  d.critical_stretch = 1.0;  // damage bookkeeping on, as in a fracture run; nothing fails
  const int layers = o.dim == 3 ? o.n : 1;
  for (int z = 0; z < layers; ++z)
    for (int y = 0; y < o.n; ++y)
      for (int x = 0; x < o.n; ++x) d.reference_position.emplace_back(x * dx, y * dx, z * dx);
  if (o.morton) {
    // Z-order: interleave the bits of the lattice coordinates (10 bits each, n <= 1024).
    auto spread = [](std::uint64_t v) {
      std::uint64_t r = 0;
      for (int b = 0; b < 10; ++b) r |= ((v >> b) & 1) << (3 * b);
      return r;
    };
    auto code = [&](const Vec3& p) {
      return spread(std::uint64_t(std::llround(p.x() / dx))) |
             spread(std::uint64_t(std::llround(p.y() / dx))) << 1 |
             spread(std::uint64_t(std::llround(p.z() / dx))) << 2;
    };
    std::sort(d.reference_position.begin(), d.reference_position.end(),
              [&](const Vec3& a, const Vec3& b) { return code(a) < code(b); });
  }
  std::mt19937 rng(1);
  if (o.jitter > 0) {
    std::uniform_real_distribution<double> j(-o.jitter * dx, o.jitter * dx);
    for (Vec3& p : d.reference_position)
      for (int c = 0; c < o.dim; ++c) p[c] += j(rng);
  }
  const double cell = o.dim == 3 ? dx * dx * dx : dx * dx;
  d.volume.assign(d.reference_position.size(), cell);
  const int h = static_cast<int>(std::ceil(o.m)), hz = o.dim == 3 ? h : 0;
  int offsets = 0;
  for (int z = -hz; z <= hz; ++z)
    for (int y = -h; y <= h; ++y)
      for (int x = -h; x <= h; ++x)
        if ((x || y || z) && std::sqrt(double(x * x + y * y + z * z)) <= o.m * (1 + 1e-12))
          ++offsets;
  // Jittered families can hold more points than the lattice's: keep beta <= 1.
  d.full_family_volume = offsets * cell * (o.jitter > 0 ? 1.5 : 1.0);
  d.strain_measure = o.strain_measure;
  ckpd::Body body = ckpd::make_body(std::move(d));
  std::uniform_real_distribution<double> u(-1e-6, 1e-6);  // about 0.1% strain
  for (Vec3& x : body.displacement) x = Vec3(u(rng), u(rng), o.dim == 3 ? u(rng) : 0.0);
  return body;
}

struct Timing {
  double median = 0, min = 0, max = 0;
  double cpu = 0;  // median CPU time of the process (all threads) per evaluation, ms
};

// CPU time of the whole process (every thread), ms: unlike the wall clock, not lengthened by
// other processes' load on a shared machine (it still counts OpenMP's spinning at barriers).
double process_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return 1e3 * static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_nsec);
}

double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t k = v.size();
  return k % 2 ? v[k / 2] : 0.5 * (v[k / 2 - 1] + v[k / 2]);
}

struct Samples {
  std::vector<double> ms, cpu;
  template <class Fn>
  void once(Fn&& fn) {
    const double c0 = process_cpu_ms();
    const auto t0 = std::chrono::steady_clock::now();
    fn();
    const auto t1 = std::chrono::steady_clock::now();
    cpu.push_back(process_cpu_ms() - c0);
    ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
  }
  Timing summary() const {
    return {median_of(ms), *std::min_element(ms.begin(), ms.end()),
            *std::max_element(ms.begin(), ms.end()), median_of(cpu)};
  }
};

template <class Fn>
Timing time_runs(int reps, Fn&& fn) {
  fn();  // warm-up: first-touch of the scratch and the caches
  Samples s;
  for (int r = 0; r < reps; ++r) s.once(fn);
  return s.summary();
}

// Times two functions in alternating runs (a, b, a, b, ...) after a warm-up of each.
template <class FnA, class FnB>
std::pair<Timing, Timing> time_alternately(int reps, FnA&& a, FnB&& b) {
  a();
  b();
  Samples sa, sb;
  for (int r = 0; r < reps; ++r) {
    sa.once(a);
    sb.once(b);
  }
  return {sa.summary(), sb.summary()};
}

// --bonds-only: the bond-only kernel against the general path, alternately, per thread count.
int bonds_only_bench(const Options& o, ckpd::Body& body) {
  ckpd::Body general = body;
  general.upper_bonds.reset();
  ckpd::SymmetricKernelWorkspace workspace, general_workspace;
  const double bonds =
      static_cast<double>(ckpd::compute_internal_force_symmetric(body, o.energy, workspace).bonds);
  std::printf("%dD bond-only %s block %d^%d, m = %.3f (C2 = C3 = 0)%s: %zu points, %.0f bonds\n",
              o.dim, o.jitter > 0 ? "jittered" : "lattice", o.n, o.dim, o.m,
              o.energy ? ", with energy" : "", body.size(), bonds);
  double worst = 0;
  for (const int threads : o.threads) {
    omp_set_num_threads(threads);
    const auto [fast, slow] = time_alternately(
        o.reps, [&] { ckpd::compute_internal_force_symmetric(body, o.energy, workspace); },
        [&] { ckpd::compute_internal_force_symmetric(general, o.energy, general_workspace); });
    std::printf("threads %d\n", threads);
    std::printf("  bond-only  %8.2f ms/step  %8.2f ms CPU/step  %.3g bonds/s per core of CPU\n",
                fast.median, fast.cpu, bonds / (fast.cpu * 1e-3));
    std::printf("  general    %8.2f ms/step  %8.2f ms CPU/step  %.3g bonds/s per core of CPU\n",
                slow.median, slow.cpu, bonds / (slow.cpu * 1e-3));
    std::printf("  gain       %8.2fx wall, %.2fx CPU\n", slow.median / fast.median,
                slow.cpu / fast.cpu);
    for (std::size_t i = 0; i < body.size(); ++i)
      worst = std::max(worst, (body.force_density[i] - general.force_density[i]).norm());
  }
  std::printf("largest |bond-only - general| force: %.3g (0: the same bits)\n", worst);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  try {
    o = parse(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "kernel_bench: %s\n", e.what());
    return 2;
  }
  ckpd::Body body = lattice_body(o);
  if (o.bonds_only) return bonds_only_bench(o, body);
  ckpd::SymmetricKernelWorkspace workspace;
  const ckpd::SymmetricKernelStats stats =
      ckpd::compute_internal_force_symmetric(body, o.energy, workspace);
  // The work that matters: three-neighbour sets in 3D, two-neighbour sets in 2D. The reference
  // evaluates each unordered set once per centre (N/6 resp. N/2 terms), the fast kernel each
  // tetrahedron (triangle) once: N/24 (N/6) when no set is degenerate from some vertices only.
  const bool three = o.dim == 3;
  const double ordered =
      static_cast<double>(three ? body.total_three_neighbour() : body.total_two_neighbour());
  const double sets = static_cast<double>(three ? stats.tetrahedra : stats.triangles);
  const char* set_name = three ? "tetrahedra" : "triangles";
  std::printf("%s %s block %d^%d, m = %.3f, E = 210 GPa, nu = %.2f%s (C2 = %g, C3 = %g)%s\n",
              three ? "3D" : "2D", o.jitter > 0 ? "jittered" : "lattice", o.n, o.dim, o.m, o.nu,
              three ? "" : " plane stress", body.constants.c2, body.constants.c3,
              o.energy ? ", with energy" : "");
  std::printf("points %zu, bonds %zu (unordered), N2 total %llu, N3 total %llu (ordered)\n",
              body.size(), body.bond_count(),
              static_cast<unsigned long long>(body.total_two_neighbour()),
              static_cast<unsigned long long>(body.total_three_neighbour()));
  std::printf(
      "per step: reference evaluates %.0f unordered %s terms (N%d/%d), the fast kernel %.0f %s "
      "(N%d/%d = %.0f; %llu of them vertex by vertex)\n",
      ordered / (three ? 6 : 2), three ? "three-neighbour" : "two-neighbour", three ? 3 : 2,
      three ? 6 : 2, sets, set_name, three ? 3 : 2, three ? 24 : 6, ordered / (three ? 24 : 6),
      static_cast<unsigned long long>(three ? stats.tetrahedra_per_vertex
                                            : stats.triangles_per_vertex));
  if (body.stencil)
    std::printf("lattice stencil: %zu upper offsets, %zu pairs, %zu triples, %.2f MB\n",
                body.stencil->slots, body.stencil->pairs, body.stencil->triples,
                static_cast<double>(body.stencil->bytes()) / 1e6);
  else
    std::printf("lattice stencil: none (%s)\n", body.stencil_note.c_str());
  std::printf("OpenMP max threads %d; reps %d (fast), %d (reference), medians\n\n",
              omp_get_max_threads(), o.reps, o.ref_reps);
  // The same body on the general path, timed alternately with the stencil path so that both
  // see the same machine load; their ratio is the stencil's gain.
  // As a point cloud of this size has it (make_body): its centres' adjacency rows in a table.
  ckpd::Body general = body;
  general.stencil.reset();
  general.upper_rows = ckpd::build_upper_rows(general);
  ckpd::SymmetricKernelWorkspace general_workspace;

  std::vector<double> ref_ms, fast_ms;
  double worst = -1;  // < 0: no comparison made
  for (const int threads : o.threads) {
    omp_set_num_threads(threads);
    std::printf("threads %d\n", threads);
    // --ref-reps 0 skips the reference and the comparison (fast-kernel profiling).
    std::vector<Vec3> reference;
    if (o.ref_reps > 0) {
      const Timing ref =
          time_runs(o.ref_reps, [&] { ckpd::compute_internal_force(body, o.energy); });
      reference = body.force_density;
      ref_ms.push_back(ref.median);
      std::printf(
          "  reference  %9.1f ms/step (min %.1f, max %.1f)  %.3g ordered N%d "
          "interactions/s\n",
          ref.median, ref.min, ref.max, ordered / (ref.median * 1e-3), three ? 3 : 2);
    }
    Timing fast, slow;
    if (body.stencil) {
      const auto [a, b] = time_alternately(
          o.reps, [&] { ckpd::compute_internal_force_symmetric(body, o.energy, workspace); },
          [&] { ckpd::compute_internal_force_symmetric(general, o.energy, general_workspace); });
      fast = a;
      slow = b;
    } else {
      fast = time_runs(o.reps,
                       [&] { ckpd::compute_internal_force_symmetric(body, o.energy, workspace); });
    }
    fast_ms.push_back(fast.median);
    std::printf(
        "  fast       %9.1f ms/step (min %.1f, max %.1f)  %.3g ordered N%d "
        "interactions/s equivalent, %.3g %s/s\n",
        fast.median, fast.min, fast.max, ordered / (fast.median * 1e-3), three ? 3 : 2,
        sets / (fast.median * 1e-3), set_name);
    std::printf("  fast       %9.1f ms CPU/step (all threads)  %.3g %s/s per core of CPU time\n",
                fast.cpu, sets / (fast.cpu * 1e-3), set_name);
    if (body.stencil) {
      double diff = 0, scale = 0;
      for (std::size_t i = 0; i < body.size(); ++i) {
        scale = std::max(scale, general.force_density[i].norm());
        diff = std::max(diff, (general.force_density[i] - body.force_density[i]).norm());
      }
      std::printf(
          "  general    %9.1f ms/step (min %.1f, max %.1f)  the fast kernel without the "
          "stencil\n  stencil gain %7.2fx (general / stencil, alternating runs), "
          "|difference| / max force %.1e\n",
          slow.median, slow.min, slow.max, slow.median / fast.median, diff / scale);
      std::printf(
          "  general    %9.1f ms CPU/step (all threads)  %.3g %s/s per core of CPU time; "
          "stencil gain in CPU time %.2fx\n",
          slow.cpu, sets / (slow.cpu * 1e-3), set_name, slow.cpu / fast.cpu);
    }
    if (!reference.empty()) {
      std::printf("  speed-up   %9.2fx\n", ref_ms.back() / fast.median);
      double scale = 0, diff = 0;
      for (std::size_t i = 0; i < body.size(); ++i) {
        scale = std::max(scale, reference[i].norm());
        diff = std::max(diff, (body.force_density[i] - reference[i]).norm());
      }
      worst = std::max(worst, diff / scale);
    }
  }
  if (o.threads.size() > 1) {
    std::printf("\nthread scaling %d -> %d threads: fast %.2fx", o.threads.front(),
                o.threads.back(), fast_ms.front() / fast_ms.back());
    if (!ref_ms.empty()) std::printf(", reference %.2fx", ref_ms.front() / ref_ms.back());
    std::printf("\n");
  }
  if (worst >= 0) std::printf("largest |fast - reference| / max |reference force|: %.2e\n", worst);
  return 0;
}
