// The machine's floating-point peak per core for the instruction set this build was made for
// (CKPD_ARCH, like every target): independent chains of fused multiply-adds, no memory traffic,
// no dependency between the accumulators, so the FMA units, not their latency, are the limit.
// The roofline of docs/PERFORMANCE.md divides the kernels' achieved flop rate by this.
//
//   fma_peak [--threads 1,2] [--reps 7] [--ms 200]
//
// For each vector width the build can hold (1 double, and 2, 4, 8 where the instruction set has
// registers that wide) prints the median (min, max) GFLOP/s per core at each thread count, one
// FMA being 2 flops per lane: per second of the CPU time each thread got (the hardware's rate,
// not lowered by other processes sharing the cores) and per second of wall clock (what a kernel
// timed by the wall clock, as kernel_bench is, could reach on the machine as loaded then).
// Compiled with -ffp-contract=fast -fno-tree-vectorize (bench/CMakeLists.txt; no vectoriser
// merging the scalar chains into vectors): acc * m + a is one FMA where the build has FMA, a
// multiply and an add (the same 2 flops) where it has not.
#include <omp.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {
template <int W>
struct Lanes {
  typedef double type __attribute__((vector_size(W * sizeof(double))));
};
template <>
struct Lanes<1> {
  typedef double type;
};

// K independent accumulators: K >= FMA latency x FMA units (4 x 2 on Zen 3/4) keeps every unit
// busy. 12 fit the 16 vector registers of AVX2 with the two constants; AVX-512 has 32.
constexpr int kChains = 12;

// Runs `iterations` rounds of kChains FMAs of width W; returns a value that depends on all of
// them (so that none is dropped).
template <int W>
__attribute__((noinline)) double run_chains(long iterations, double seed) {
  using V = typename Lanes<W>::type;
  V acc[kChains];
  for (int k = 0; k < kChains; ++k) acc[k] = V{} + (seed + 0.01 * k);
  const V m = V{} + 0.999999, a = V{} + 1e-7;
  for (long i = 0; i < iterations; ++i) {
#pragma GCC unroll 12
    for (int k = 0; k < kChains; ++k) acc[k] = acc[k] * m + a;
  }
  V sum = acc[0];
  for (int k = 1; k < kChains; ++k) sum += acc[k];
  double s = 0;
  if constexpr (W == 1) {
    s = sum;
  } else {
    for (int l = 0; l < W; ++l) s += sum[l];
  }
  return s;
}

double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

struct Rate {
  double wall;  // GFLOP/s per core over the wall-clock time
  double cpu;   // GFLOP/s per second of CPU time each thread got (not lowered by other load)
};

// GFLOP/s per core of one timed round on `threads` threads, each running its own chains.
template <int W>
Rate gflops_per_core(int threads, double target_ms) {
  // Calibrate the iteration count to about target_ms on one thread.
  long iterations = 1 << 16;
  for (;;) {
    const auto t0 = std::chrono::steady_clock::now();
    volatile double sink = run_chains<W>(iterations, 1.0);
    (void)sink;
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (ms > target_ms / 4) {
      iterations = static_cast<long>(iterations * target_ms / ms);
      break;
    }
    iterations *= 4;
  }
  std::vector<double> seconds(threads, 0), cpu_seconds(threads, 0);
  double checksum = 0;
#pragma omp parallel num_threads(threads) reduction(+ : checksum)
  {
    const int t = omp_get_thread_num();
#pragma omp barrier
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = thread_cpu_seconds();
    checksum += run_chains<W>(iterations, 1.0 + t);
    cpu_seconds[t] = thread_cpu_seconds() - c0;
    seconds[t] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  if (!(checksum > 0)) throw std::runtime_error("fma_peak: chains lost");
  const double flops = 2.0 * W * kChains * static_cast<double>(iterations);
  Rate rate{0, 0};  // each thread's own rate, averaged: per core
  for (int t = 0; t < threads; ++t) {
    rate.wall += flops / seconds[t] / threads / 1e9;
    rate.cpu += flops / cpu_seconds[t] / threads / 1e9;
  }
  return rate;
}

struct Stats {
  double median, min, max;
};

Stats stats(std::vector<double> r) {
  std::sort(r.begin(), r.end());
  return {r[r.size() / 2], r.front(), r.back()};
}

template <int W>
void report(const std::vector<int>& threads, int reps, double ms) {
  for (int t : threads) {
    std::vector<double> wall, cpu;
    for (int k = 0; k < reps; ++k) {
      const Rate r = gflops_per_core<W>(t, ms);
      wall.push_back(r.wall);
      cpu.push_back(r.cpu);
    }
    const Stats w = stats(wall), c = stats(cpu);
    std::printf(
        "width %d doubles, %d thread%s: %.2f GFLOP/s per core of CPU time (min %.2f, max %.2f); "
        "wall clock %.2f (min %.2f, max %.2f)\n",
        W, t, t == 1 ? "" : "s", c.median, c.min, c.max, w.median, w.min, w.max);
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> threads{1, 2};
  int reps = 7;
  double ms = 200;
  try {
    for (int a = 1; a < argc; ++a) {
      const std::string key = argv[a];
      if (a + 1 >= argc) throw std::invalid_argument(key + " needs a value");
      const std::string value = argv[++a];
      if (key == "--threads") {
        threads.clear();
        std::stringstream list(value);
        for (std::string item; std::getline(list, item, ',');) threads.push_back(std::stoi(item));
      } else if (key == "--reps") {
        reps = std::stoi(value);
      } else if (key == "--ms") {
        ms = std::stod(value);
      } else {
        throw std::invalid_argument("unknown option " + key);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fma_peak: %s\n", e.what());
    return 2;
  }
#ifdef __FMA__
  std::printf("fused multiply-add: yes (FMA)\n");
#else
  std::printf("fused multiply-add: no (a multiply and an add, 2 flops)\n");
#endif
  report<1>(threads, reps, ms);
  report<2>(threads, reps, ms);
#ifdef __AVX__
  report<4>(threads, reps, ms);
#endif
#ifdef __AVX512F__
  report<8>(threads, reps, ms);
#endif
  return 0;
}
