// Prototype, not used by bodies/: the general path's tetrahedron loop of one point (all four
// vertices active, linear strain, no energy, no penalty), as bodies/symmetric/tetrahedron_loop.hpp
// evaluates it, against batched evaluations that fill a vector register, to choose the means for
// issue 21 (docs/PERFORMANCE.md, "Batched tetrahedra").
//
//   tet_batch_bench [--m 3.015] [--jitter 0.1] [--reps 9] [--points 200]
//
// The family of a lattice point (spacing 1, horizon m, upper half: slots above the centre),
// perturbed by up to +-jitter per component in the reference and by a small random strain in the
// current configuration. For each bonded pair (a, b) of slots, the tetrahedra {i, a, b, c} with c
// > b bonded to both (cand = adj[a] & adj[b] above b), as in the kernel:
//   scalar   the kernel's loop: one c at a time, found by countr_zero over the candidate bits;
//   dense8   the 64 slots of a word in batches of 8 (GCC vector extensions; one AVX-512 register
//            under CKPD_ARCH=native here), every lane evaluated, the lanes whose bit is clear (or
//            whose tetrahedron is ill-conditioned) masked to f = 0;
//   dense4   the same in batches of 4 (one AVX2 register);
//   packed8  the candidates' slots gathered into a packed list first, then batches of 8 lanes
//            that are all live (the remainder masked), the loads gathers.
// Each variant's forces on the slots and on the centre are compared with the scalar loop's (to
// 1e-12 of the largest); times (this thread's CPU time: the machine is shared) are medians over
// --reps of all pairs of
// --points point families.
#include <time.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

struct Family {
  int m = 0;                       // slots (m <= 64 here: one word)
  std::vector<double> Rx, Ry, Rz;  // reference offsets
  std::vector<double> rx, ry, rz;  // current offsets
  std::vector<double> k3;          // per-slot force weights
  std::vector<std::uint64_t> adj;  // adj[a]: slots bonded to a
};

struct Pair {
  int a, b;
  double pq[3];   // p x q (current)
  double RPQ[3];  // P x Q (reference)
  double pa[3], pb[3];
  std::uint64_t cand;
};

struct Result {
  std::vector<double> fx, fy, fz;  // per slot
  double ci[3] = {0, 0, 0};        // on the centre
};

Family make_family(double horizon, double jitter, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  Family f;
  const int r = static_cast<int>(std::ceil(horizon));
  std::vector<std::array<double, 3>> X;
  for (int z = -r; z <= r; ++z)
    for (int y = -r; y <= r; ++y)
      for (int x = -r; x <= r; ++x) {
        if (x * x + y * y + z * z > horizon * horizon) continue;
        // Upper half: later in (z, y, x) order than the centre.
        if (z < 0 || (z == 0 && (y < 0 || (y == 0 && x <= 0)))) continue;
        X.push_back({x + jitter * u(rng), y + jitter * u(rng), z + jitter * u(rng)});
      }
  if (X.size() > 64) X.resize(64);
  f.m = static_cast<int>(X.size());
  const double strain[3][3] = {{1e-3 * u(rng), 1e-3 * u(rng), 1e-3 * u(rng)},
                               {1e-3 * u(rng), 1e-3 * u(rng), 1e-3 * u(rng)},
                               {1e-3 * u(rng), 1e-3 * u(rng), 1e-3 * u(rng)}};
  for (const auto& p : X) {
    f.Rx.push_back(p[0]);
    f.Ry.push_back(p[1]);
    f.Rz.push_back(p[2]);
    double q[3];
    for (int d = 0; d < 3; ++d)
      q[d] = p[d] + strain[d][0] * p[0] + strain[d][1] * p[1] + strain[d][2] * p[2] + 1e-4 * u(rng);
    f.rx.push_back(q[0]);
    f.ry.push_back(q[1]);
    f.rz.push_back(q[2]);
    f.k3.push_back(1 + 0.1 * u(rng));
  }
  f.adj.assign(f.m, 0);
  for (int a = 0; a < f.m; ++a)
    for (int b = 0; b < f.m; ++b) {
      const double dx = f.Rx[a] - f.Rx[b], dy = f.Ry[a] - f.Ry[b], dz = f.Rz[a] - f.Rz[b];
      if (a != b && dx * dx + dy * dy + dz * dz <= horizon * horizon)
        f.adj[a] |= std::uint64_t{1} << b;
    }
  return f;
}

std::vector<Pair> make_pairs(const Family& f) {
  std::vector<Pair> pairs;
  for (int a = 0; a < f.m; ++a)
    for (int b = a + 1; b < f.m; ++b) {
      if (!((f.adj[a] >> b) & 1)) continue;
      Pair p;
      p.a = a;
      p.b = b;
      const double pa[3] = {f.rx[a], f.ry[a], f.rz[a]}, pb[3] = {f.rx[b], f.ry[b], f.rz[b]};
      const double Pa[3] = {f.Rx[a], f.Ry[a], f.Rz[a]}, Pb[3] = {f.Rx[b], f.Ry[b], f.Rz[b]};
      for (int d = 0; d < 3; ++d) {
        p.pa[d] = pa[d];
        p.pb[d] = pb[d];
      }
      p.pq[0] = pa[1] * pb[2] - pa[2] * pb[1];
      p.pq[1] = pa[2] * pb[0] - pa[0] * pb[2];
      p.pq[2] = pa[0] * pb[1] - pa[1] * pb[0];
      p.RPQ[0] = Pa[1] * Pb[2] - Pa[2] * Pb[1];
      p.RPQ[1] = Pa[2] * Pb[0] - Pa[0] * Pb[2];
      p.RPQ[2] = Pa[0] * Pb[1] - Pa[1] * Pb[0];
      const std::uint64_t above = b == 63 ? 0 : ~std::uint64_t{0} << (b + 1);
      p.cand = f.adj[a] & f.adj[b] & above;
      if (p.cand) pairs.push_back(p);
    }
  return pairs;
}

// CPU time of this thread: the machine is shared, and a wall-clock time would measure the load.
double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

inline double sign_of(double v) {
  return v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0);
}

constexpr double kWell3 = 1e-3;  // |V| below: ill-conditioned (the kernel's separate path)

// After the c loop: the kernel's forces on i, j (slot a), k (slot b) from S and F.
inline void finish(const Pair& pr, const double S[3], double F, const Family& f, Result& out) {
  const double qp[3] = {pr.pb[0] - pr.pa[0], pr.pb[1] - pr.pa[1], pr.pb[2] - pr.pa[2]};
  out.ci[0] += qp[1] * S[2] - qp[2] * S[1] + pr.pq[0] * F;
  out.ci[1] += qp[2] * S[0] - qp[0] * S[2] + pr.pq[1] * F;
  out.ci[2] += qp[0] * S[1] - qp[1] * S[0] + pr.pq[2] * F;
  const int a = pr.a, b = pr.b;
  out.fx[a] -= f.k3[a] * (pr.pb[1] * S[2] - pr.pb[2] * S[1]);
  out.fy[a] -= f.k3[a] * (pr.pb[2] * S[0] - pr.pb[0] * S[2]);
  out.fz[a] -= f.k3[a] * (pr.pb[0] * S[1] - pr.pb[1] * S[0]);
  out.fx[b] -= f.k3[b] * (S[1] * pr.pa[2] - S[2] * pr.pa[1]);
  out.fy[b] -= f.k3[b] * (S[2] * pr.pa[0] - S[0] * pr.pa[2]);
  out.fz[b] -= f.k3[b] * (S[0] * pr.pa[1] - S[1] * pr.pa[0]);
}

// The kernel's loop (tetrahedron_loop.hpp, the general path's `full` sets).
__attribute__((noinline)) std::uint64_t scalar(const Family& f, const std::vector<Pair>& pairs,
                                               Result& out) {
  const double* __restrict Rx = f.Rx.data();
  const double* __restrict Ry = f.Ry.data();
  const double* __restrict Rz = f.Rz.data();
  const double* __restrict rx = f.rx.data();
  const double* __restrict ry = f.ry.data();
  const double* __restrict rz = f.rz.data();
  const double* __restrict k3 = f.k3.data();
  double* __restrict fx = out.fx.data();
  double* __restrict fy = out.fy.data();
  double* __restrict fz = out.fz.data();
  std::uint64_t n = 0;
  for (const Pair& pr : pairs) {
    const double* pq = pr.pq;
    const double* RPQ = pr.RPQ;
    double S[3] = {0, 0, 0}, F = 0;
    for (std::uint64_t full = pr.cand; full; full &= full - 1) {
      const std::size_t c = static_cast<std::size_t>(std::countr_zero(full));
      const double signed_V = RPQ[0] * Rx[c] + RPQ[1] * Ry[c] + RPQ[2] * Rz[c];
      const double V = std::abs(signed_V);
      if (!(V > kWell3)) continue;
      const double r[3] = {rx[c], ry[c], rz[c]};
      const double v = pq[0] * r[0] + pq[1] * r[1] + pq[2] * r[2];
      const double fc = v / V - sign_of(v);
      S[0] += fc * r[0];
      S[1] += fc * r[1];
      S[2] += fc * r[2];
      F += fc;
      const double kl = k3[c] * fc;
      fx[c] -= kl * pq[0];
      fy[c] -= kl * pq[1];
      fz[c] -= kl * pq[2];
      ++n;
    }
    finish(pr, S, F, f, out);
  }
  return n;
}

template <int W>
struct Lanes {
  typedef double vd __attribute__((vector_size(W * sizeof(double))));
  typedef std::int64_t vi __attribute__((vector_size(W * sizeof(double))));
};

template <int W>
inline typename Lanes<W>::vd load(const double* p) {
  typename Lanes<W>::vd v;
  __builtin_memcpy(&v, p, sizeof v);
  return v;
}
template <int W>
inline void store(double* p, typename Lanes<W>::vd v) {
  __builtin_memcpy(p, &v, sizeof v);
}

// Every lane of the word, batches of W slots; lanes not in cand (or ill-conditioned) get f = 0.
// The slot arrays are padded to 64 (slots past m are zero).
template <int W>
__attribute__((noinline)) std::uint64_t dense(const Family& f, const std::vector<Pair>& pairs,
                                              Result& out) {
  using vd = typename Lanes<W>::vd;
  using vi = typename Lanes<W>::vi;
  vi lane_bit;
  for (int l = 0; l < W; ++l) lane_bit[l] = std::int64_t{1} << l;
  std::uint64_t n = 0;
  for (const Pair& pr : pairs) {
    vd S0 = vd{} + 0.0, S1 = S0, S2 = S0, Fv = S0;
    const vd q0 = vd{} + pr.pq[0], q1 = vd{} + pr.pq[1], q2 = vd{} + pr.pq[2];
    const vd R0 = vd{} + pr.RPQ[0], R1 = vd{} + pr.RPQ[1], R2 = vd{} + pr.RPQ[2];
    const int first = (pr.b + 1) / W * W;
    for (int c0 = first; c0 < 64; c0 += W) {
      const std::uint64_t bits = (pr.cand >> c0) & ((std::uint64_t{1} << W) - 1);
      if (!bits) continue;
      const vi live = (vi{} + static_cast<std::int64_t>(bits)) & lane_bit;
      const vd sV = R0 * load<W>(&f.Rx[c0]) + R1 * load<W>(&f.Ry[c0]) + R2 * load<W>(&f.Rz[c0]);
      const vd V = sV < 0 ? -sV : sV;
      const vi use = (live != 0) & (V > kWell3);
      const vd r0 = load<W>(&f.rx[c0]), r1 = load<W>(&f.ry[c0]), r2 = load<W>(&f.rz[c0]);
      const vd v = q0 * r0 + q1 * r1 + q2 * r2;
      const vd sgn = v > 0 ? vd{} + 1.0 : (v < 0 ? vd{} - 1.0 : vd{} + 0.0);
      const vd safe_V = use ? V : vd{} + 1.0;
      const vd fc = use ? v / safe_V - sgn : vd{} + 0.0;
      S0 += fc * r0;
      S1 += fc * r1;
      S2 += fc * r2;
      Fv += fc;
      const vd kl = load<W>(&f.k3[c0]) * fc;
      store<W>(&out.fx[c0], load<W>(&out.fx[c0]) - kl * q0);
      store<W>(&out.fy[c0], load<W>(&out.fy[c0]) - kl * q1);
      store<W>(&out.fz[c0], load<W>(&out.fz[c0]) - kl * q2);
      n += static_cast<std::uint64_t>(std::popcount(bits));
    }
    double S[3] = {0, 0, 0}, F = 0;
    for (int l = 0; l < W; ++l) {
      S[0] += S0[l];
      S[1] += S1[l];
      S[2] += S2[l];
      F += Fv[l];
    }
    finish(pr, S, F, f, out);
  }
  return n;
}

// The candidates packed first (their slot numbers in a list), then full batches of W gathered
// lanes; the last batch masked. Scatter of the slot forces: the c of one pair are distinct.
template <int W>
__attribute__((noinline)) std::uint64_t packed(const Family& f, const std::vector<Pair>& pairs,
                                               Result& out) {
  using vd = typename Lanes<W>::vd;
  using vi = typename Lanes<W>::vi;
  std::uint64_t n = 0;
  int list[64 + W];
  for (const Pair& pr : pairs) {
    int count = 0;
    for (std::uint64_t bits = pr.cand; bits; bits &= bits - 1)
      list[count++] = std::countr_zero(bits);
    for (int k = count; k < count + W; ++k) list[k] = 63;  // a valid slot; masked below
    vd S0 = vd{} + 0.0, S1 = S0, S2 = S0, Fv = S0;
    const vd q0 = vd{} + pr.pq[0], q1 = vd{} + pr.pq[1], q2 = vd{} + pr.pq[2];
    for (int k0 = 0; k0 < count; k0 += W) {
      vd Rx, Ry, Rz, r0, r1, r2, k3;
      vi live;
      for (int l = 0; l < W; ++l) {
        const int c = list[k0 + l];
        Rx[l] = f.Rx[c];
        Ry[l] = f.Ry[c];
        Rz[l] = f.Rz[c];
        r0[l] = f.rx[c];
        r1[l] = f.ry[c];
        r2[l] = f.rz[c];
        k3[l] = f.k3[c];
        live[l] = k0 + l < count ? -1 : 0;
      }
      const vd sV = pr.RPQ[0] * Rx + pr.RPQ[1] * Ry + pr.RPQ[2] * Rz;
      const vd V = sV < 0 ? -sV : sV;
      const vi use = live & (V > kWell3);
      const vd v = q0 * r0 + q1 * r1 + q2 * r2;
      const vd sgn = v > 0 ? vd{} + 1.0 : (v < 0 ? vd{} - 1.0 : vd{} + 0.0);
      const vd safe_V = use ? V : vd{} + 1.0;
      const vd fc = use ? v / safe_V - sgn : vd{} + 0.0;
      S0 += fc * r0;
      S1 += fc * r1;
      S2 += fc * r2;
      Fv += fc;
      const vd kl = k3 * fc;
      const vd dx = kl * q0, dy = kl * q1, dz = kl * q2;
      for (int l = 0; l < W && k0 + l < count; ++l) {
        const int c = list[k0 + l];
        out.fx[c] -= dx[l];
        out.fy[c] -= dy[l];
        out.fz[c] -= dz[l];
      }
    }
    n += static_cast<std::uint64_t>(count);
    double S[3] = {0, 0, 0}, F = 0;
    for (int l = 0; l < W; ++l) {
      S[0] += S0[l];
      S[1] += S1[l];
      S[2] += S2[l];
      F += Fv[l];
    }
    finish(pr, S, F, f, out);
  }
  return n;
}

Result zero_result() {
  Result r;
  r.fx.assign(64 + 8, 0);
  r.fy.assign(64 + 8, 0);
  r.fz.assign(64 + 8, 0);
  return r;
}

double difference(const Result& a, const Result& b) {
  double big = 0, diff = 0;
  for (std::size_t k = 0; k < a.fx.size(); ++k) {
    big = std::max({big, std::abs(a.fx[k]), std::abs(a.fy[k]), std::abs(a.fz[k])});
    diff = std::max({diff, std::abs(a.fx[k] - b.fx[k]), std::abs(a.fy[k] - b.fy[k]),
                     std::abs(a.fz[k] - b.fz[k])});
  }
  for (int d = 0; d < 3; ++d) {
    big = std::max(big, std::abs(a.ci[d]));
    diff = std::max(diff, std::abs(a.ci[d] - b.ci[d]));
  }
  return diff / big;
}

}  // namespace

int main(int argc, char** argv) {
  double horizon = 3.015, jitter = 0.1;
  int reps = 9, points = 200;
  try {
    for (int a = 1; a < argc; ++a) {
      const std::string key = argv[a];
      if (a + 1 >= argc) throw std::invalid_argument(key + " needs a value");
      const std::string value = argv[++a];
      if (key == "--m") {
        horizon = std::stod(value);
      } else if (key == "--jitter") {
        jitter = std::stod(value);
      } else if (key == "--reps") {
        reps = std::stoi(value);
      } else if (key == "--points") {
        points = std::stoi(value);
      } else {
        throw std::invalid_argument("unknown option " + key);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tet_batch_bench: %s\n", e.what());
    return 2;
  }
  std::mt19937_64 rng(21);
  std::vector<Family> families;
  std::vector<std::vector<Pair>> pairs;
  for (int p = 0; p < points; ++p) {
    families.push_back(make_family(horizon, jitter, rng));
    Family& f = families.back();
    for (auto* v : {&f.Rx, &f.Ry, &f.Rz, &f.rx, &f.ry, &f.rz, &f.k3}) v->resize(64 + 8, 0.0);
    pairs.push_back(make_pairs(f));
  }
  std::printf("%d families of %d slots (m = %.3f, jitter %.2f), %zu pairs each\n", points,
              families[0].m, horizon, jitter, pairs[0].size());
  using Variant = std::uint64_t (*)(const Family&, const std::vector<Pair>&, Result&);
  const struct {
    const char* name;
    Variant run;
  } variants[] = {{"scalar", scalar},
                  {"dense8", dense<8>},
                  {"dense4", dense<4>},
                  {"packed8", packed<8>},
                  {"packed4", packed<4>}};
  std::vector<Result> reference;
  double scalar_ns = 0;
  for (const auto& variant : variants) {
    std::vector<double> ns;
    std::uint64_t tets = 0;
    double worst = 0;
    for (int r = 0; r < reps; ++r) {
      std::vector<Result> results(points, zero_result());
      tets = 0;
      const double t0 = thread_cpu_seconds();
      for (int p = 0; p < points; ++p) tets += variant.run(families[p], pairs[p], results[p]);
      const double s = thread_cpu_seconds() - t0;
      ns.push_back(1e9 * s / static_cast<double>(tets));
      if (reference.empty()) reference = results;
      for (int p = 0; p < points; ++p)
        worst = std::max(worst, difference(reference[p], results[p]));
    }
    std::sort(ns.begin(), ns.end());
    const double median = ns[ns.size() / 2];
    if (scalar_ns == 0) scalar_ns = median;
    std::printf(
        "%-8s %.2f ns per tetrahedron (min %.2f, max %.2f), %.2fx scalar, %llu tetrahedra, "
        "largest difference from scalar %.2e of the largest force%s\n",
        variant.name, median, ns.front(), ns.back(), scalar_ns / median,
        static_cast<unsigned long long>(tets), worst, worst > 1e-12 ? "  FAIL" : "");
    if (worst > 1e-12) return 1;
  }
  return 0;
}
