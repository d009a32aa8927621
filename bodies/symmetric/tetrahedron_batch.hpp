#pragma once
// Batched tetrahedra (docs/PERFORMANCE.md, "Batched tetrahedra in the kernel"): the tetrahedra
// {i, a, b, c} of one pair whose four vertices are all active, evaluated 4 slots c at a time.
// A block is the 4 slots from the lowest such c not yet done (c0 = that c: blocks start at a
// candidate, not at a multiple of 4, which covers a word's candidates with fewer blocks; the
// per-slot arrays are padded past the last word, context.hpp), evaluated whole: contiguous loads
// of the slots' offsets and weights, every lane computed, the lanes without a tetrahedron (or,
// on the general path, with an ill-conditioned one) masked to f = 0 and en = 0; no gather. Built
// when the compiler targets AVX2 (one 256-bit register of 4 doubles; GCC vector extensions);
// other builds keep the scalar loop. The Seth-Hill measures (m != 1/2) are batched on the general
// path, their strain lane by lane where it needs log1p/expm1 (seth_hill_lanes). Per tetrahedron the
// lanes compute what the scalar loop computes, operation for operation; only the order of the sums
// over c (S, F, E: per lane, then across lanes) differs.
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <utility>

#include "bodies/symmetric/pair.hpp"

#if defined(__AVX2__)
#include <immintrin.h>
#define CKPD_BATCHED_TETRAHEDRA 1
#endif

namespace ckpd::symmetric {

// Slots per batch (0: no batched path in this build). CKPD_TETRAHEDRON_BATCH=8 (AVX-512 builds
// only) selects blocks of 8, measured against 4 in docs/PERFORMANCE.md.
#if defined(CKPD_BATCHED_TETRAHEDRA) && defined(CKPD_TETRAHEDRON_BATCH) && \
    CKPD_TETRAHEDRON_BATCH == 8 && defined(__AVX512F__)
#define CKPD_TETRAHEDRON_LANES 8
#elif defined(CKPD_BATCHED_TETRAHEDRA)
#define CKPD_TETRAHEDRON_LANES 4
#else
#define CKPD_TETRAHEDRON_LANES 0
#endif
inline constexpr int kTetrahedronBatch = CKPD_TETRAHEDRON_LANES;
// The tetrahedron loops are inlined into the pair loop where the batch is built (measured
// there: 8-10 % less CPU time per evaluation; the pointer set-up per pair is hoisted).
#if CKPD_TETRAHEDRON_LANES > 0
#define CKPD_TETRAHEDRON_LOOP_INLINE [[gnu::always_inline]]
#else
#define CKPD_TETRAHEDRON_LOOP_INLINE
#endif
// The lanes of a block as bits.
inline constexpr std::uint64_t kBatchLanes = (std::uint64_t{1} << kTetrahedronBatch) - 1;

// Whether a model's linear-strain law (e = r - 1) is the one the batch evaluates.
template <class Model>
constexpr bool linear_strain_law() {
  if constexpr (requires {
                  std::remove_cvref_t<decltype(std::declval<const Model&>().strain)>::kLinear;
                }) {
    return std::remove_cvref_t<decltype(std::declval<const Model&>().strain)>::kLinear;
  } else {
    return false;
  }
}

// Whether a model has a strain law at all (the CKPD law: LinearStrain or SethHillStrain).
template <class Model>
constexpr bool has_strain_law() {
  return requires {
    std::remove_cvref_t<decltype(std::declval<const Model&>().strain)>::kLinear;
  };
}

// Which tetrahedra go in batches: the linear law (m = 1/2) on both paths; a Seth-Hill measure on
// the general path only. Measured (docs/PERFORMANCE.md, "Batched Seth-Hill tetrahedra"): on the
// general path the batch gains 1.2x at m = -1/2, on the stencil path it lost 1.3-1.4x against
// the scalar loop, whose stencil sets need no division for v / V.
template <class Model, bool kStencil>
constexpr bool batched_tetrahedra() {
  if constexpr (kTetrahedronBatch > 0 && Model::kTetrahedra && has_strain_law<Model>()) {
    return linear_strain_law<Model>() || !kStencil;
  } else {
    return false;
  }
}

#if defined(CKPD_BATCHED_TETRAHEDRA)

namespace batch {

constexpr int kW = kTetrahedronBatch;
using d4 = double __attribute__((vector_size(8 * kW)));
using i4 = std::int64_t __attribute__((vector_size(8 * kW)));

inline d4 load(const double* p) {
  d4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline void store(double* p, d4 v) {
  std::memcpy(p, &v, sizeof v);
}
inline d4 splat(double x) {
  return d4{} + x;
}
// Lane l is all ones where bit l of `bits` is set.
inline i4 lanes(unsigned bits) {
  i4 bit;
  for (int l = 0; l < kW; ++l) bit[l] = std::int64_t{1} << l;
  return ((i4{} + static_cast<std::int64_t>(bits)) & bit) != 0;
}
// The lanes of a mask as bits.
inline unsigned bits(i4 mask) {
#if CKPD_TETRAHEDRON_LANES == 4
  return static_cast<unsigned>(_mm256_movemask_pd(reinterpret_cast<__m256d>(mask)));
#else
  return static_cast<unsigned>(
      _mm512_cmpneq_epi64_mask(reinterpret_cast<__m512i>(mask), _mm512_setzero_si512()));
#endif
}
// Sum over the lanes, in pairs.
inline double sum(d4 v) {
#if CKPD_TETRAHEDRON_LANES == 4
  return (v[0] + v[1]) + (v[2] + v[3]);
#else
  return ((v[0] + v[1]) + (v[2] + v[3])) + ((v[4] + v[5]) + (v[6] + v[7]));
#endif
}
inline d4 abs(d4 v) {
  return v < 0 ? -v : v;
}
// sign_of per lane (sign(0) = 0).
inline d4 sign(d4 v) {
  const d4 one = splat(1.0), zero = splat(0.0);
  return v > 0 ? one : (v < 0 ? -one : zero);
}
#if CKPD_TETRAHEDRON_LANES == 4 && !(defined(__AVX512F__) && defined(__AVX512VL__))
// For each 4-bit tb, the 32-bit source elements of each lane of the expand below: lane l takes
// packed entry rank(l) = popcount(tb below l) (lanes outside tb: entry 0, zeroed after).
struct alignas(32) ExpandOrder : std::array<std::int32_t, 8> {};
inline constexpr std::array<ExpandOrder, 16> kExpandOrder = [] {
  std::array<ExpandOrder, 16> t{};
  for (unsigned tb = 0; tb < 16; ++tb) {
    int rank = 0;
    for (int l = 0; l < 4; ++l) {
      const int src = (tb >> l) & 1 ? rank++ : 0;
      t[tb][static_cast<std::size_t>(2 * l)] = 2 * src;
      t[tb][static_cast<std::size_t>(2 * l + 1)] = 2 * src + 1;
    }
  }
  return t;
}();
#endif
// The signed 1 / V of the lanes in `tb` (bit l: slot c0 + l is a triple of the stencil row) from
// the row's packed entries starting at `packed`; 0 in the other lanes.
inline d4 expand(const double* packed, unsigned tb) {
#if CKPD_TETRAHEDRON_LANES == 8
  return reinterpret_cast<d4>(_mm512_maskz_expandloadu_pd(static_cast<__mmask8>(tb), packed));
#elif defined(__AVX512F__) && defined(__AVX512VL__)
  return reinterpret_cast<d4>(_mm256_maskz_expandloadu_pd(static_cast<__mmask8>(tb), packed));
#else
  // AVX2: the popcount(tb) packed entries loaded (masked: nothing read past them), then moved
  // to their lanes by a permutation per tb, the other lanes zeroed; no branch.
  const int n = std::popcount(tb);
  const __m256i first = _mm256_cmpgt_epi64(_mm256_set1_epi64x(n), _mm256_setr_epi64x(0, 1, 2, 3));
  const __m256d loaded = _mm256_maskload_pd(packed, first);
  const __m256i order =
      _mm256_load_si256(reinterpret_cast<const __m256i*>(kExpandOrder[tb & 15].data()));
  const __m256d moved = _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(loaded), order));
  return reinterpret_cast<d4>(_mm256_and_pd(moved, reinterpret_cast<__m256d>(lanes(tb))));
#endif
}

// A pair's geometry as the batch uses it: the slots' offsets (raw pointers, held in registers
// by the caller's loop: the batch's stores are memcpy and could alias anything reached through
// memory) and p x q, P x Q broadcast to every lane.
struct Geometry {
  const double* Rx;
  const double* Ry;
  const double* Rz;
  const double* rx;
  const double* ry;
  const double* rz;
  d4 q0, q1, q2, R0, R1, R2;
  Geometry(const double* Rx_, const double* Ry_, const double* Rz_, const double* rx_,
           const double* ry_, const double* rz_, const double pq[3], const double RPQ[3])
      : Rx(Rx_),
        Ry(Ry_),
        Rz(Rz_),
        rx(rx_),
        ry(ry_),
        rz(rz_),
        q0(splat(pq[0])),
        q1(splat(pq[1])),
        q2(splat(pq[2])),
        R0(splat(RPQ[0])),
        R1(splat(RPQ[1])),
        R2(splat(RPQ[2])) {}
  // General path: the signed reference volumes P x Q . R of slots c0..c0+3.
  d4 signed_volume(std::size_t c0) const {
    return R0 * load(Rx + c0) + R1 * load(Ry + c0) + R2 * load(Rz + c0);
  }
};

// The Seth-Hill slope factor e_m(r) r^(2m - 1) and, with kStrain, e_m(r) per lane, from
// d = r - 1, operation for operation as SethHillStrain::factor and ::strain compute them: m = -1/2
// in vector arithmetic (one division), any other m lane by lane with SethHillStrain's own
// functions (log1p, expm1: no vector forms in the C library without -ffast-math), only in the
// lanes of `use` (the others, whatever d they hold, get 0: the caller masks them).
template <bool kStrain, class Strain>
inline void seth_hill_lanes(const Strain& law, d4 d, unsigned use, d4& factor, d4& strain) {
  if (law.m == -0.5) {
    const d4 r = splat(1.0) + d;
    const d4 ir = splat(1.0) / r;
    factor = d * ir * ir * ir;
    if constexpr (kStrain) strain = d / r;
    return;
  }
  // Lane by lane through plain arrays (element writes would keep the vectors in memory).
  alignas(8 * kW) double dl[kW], fl[kW] = {}, sl[kW] = {};
  store(dl, d);
  for (; use; use &= use - 1) {
    const int l = std::countr_zero(use);
    fl[l] = law.factor(dl[l]);
    if constexpr (kStrain) sl[l] = law.strain(dl[l]);
  }
  factor = load(fl);
  if constexpr (kStrain) strain = load(sl);
}

// One block of 4 slots c0..c0+3 of the pair: per lane the tetrahedron's coefficient f, its
// energy measure en (penalty included) and the current offset r of c; lanes outside `use` have
// f = en = 0.
struct Block {
  d4 r0, r1, r2, f, en;
  unsigned use = 0, inverted = 0;
};

// `live`: the lanes with a tetrahedron to evaluate (all four vertices active). General path:
// `signed_ref` the signed reference volumes, evaluated where |V| > well3 (the other live lanes
// go to `ill`). Stencil path: `signed_ref` the signed 1 / V (nonzero in the live lanes).
template <class Model, bool kEnergy, bool kPenalty, bool kStencil>
inline Block evaluate(const Model& model, const Geometry& g, std::size_t c0, unsigned live,
                      d4 signed_ref, double well3, unsigned& ill) {
  Block k;
  const d4 zero = splat(0.0), one = splat(1.0);
  i4 use = lanes(live);
  const d4 measure = abs(signed_ref);  // general: V; stencil: 1 / V
  if constexpr (kStencil) {
    ill = 0;
  } else {
    use = use & (measure > well3);
    ill = live & ~bits(use);
  }
  k.use = bits(use);
  // Lanes outside use divide by 1 (stencil: multiply by 1): finite whatever the slot holds.
  const d4 M = use ? measure : one;
  k.r0 = load(g.rx + c0);
  k.r1 = load(g.ry + c0);
  k.r2 = load(g.rz + c0);
  const d4 v = g.q0 * k.r0 + g.q1 * k.r1 + g.q2 * k.r2;
  const d4 ratio = kStencil ? v * M : v / M;  // V.over(v)
  const d4 sgn = sign(v);
  // tetrahedron_coefficient and tetrahedron_energy_measure's e: the linear law from v / V
  // itself, a Seth-Hill law from d = |v| / V - 1 (= |v / V| - 1; a collapsed tetrahedron,
  // v = 0, gets no force).
  d4 f, e = zero;
  if constexpr (linear_strain_law<Model>()) {
    f = ratio - sgn;
    if constexpr (kEnergy) e = abs(ratio) - one;
  } else {
    d4 factor;
    seth_hill_lanes<kEnergy>(model.strain, abs(ratio) - one, k.use, factor, e);
    f = v != 0 ? factor * sgn : zero;
  }
  const i4 inverted = use & (v * signed_ref < 0);  // tetrahedron_inverted: v * signed V < 0
  if constexpr (kEnergy) k.inverted = bits(inverted);
  if constexpr (kPenalty) f = inverted ? f + splat(model.pen3) * sgn : f;
  k.f = use ? f : zero;
  if constexpr (kEnergy) {
    // V e^2 (stencil: e^2 / (1/V)).
    d4 en = kStencil ? e * e / M : M * e * e;
    if constexpr (kPenalty) en = inverted ? en + splat(2 * model.pen3) * abs(v) : en;
    k.en = use ? en : zero;
  } else {
    k.en = zero;
  }
  return k;
}

// Per-lane sums over a pair's batched tetrahedra: S = sum f r, F = sum f, E = sum en.
struct Sums {
  d4 s0 = splat(0.0), s1 = splat(0.0), s2 = splat(0.0), f = splat(0.0), e = splat(0.0);
  void add(const Block& k) {
    s0 += k.f * k.r0;
    s1 += k.f * k.r1;
    s2 += k.f * k.r2;
    f += k.f;
    e += k.en;
  }
  // Adds the lanes' sums to the scalar ones.
  void into(double S[3], double& F, double& E) const {
    S[0] += sum(s0);
    S[1] += sum(s1);
    S[2] += sum(s2);
    F += sum(f);
    E += sum(e);
  }
};

// slot_c -= k * pq per lane (the fourth vertex's force), x, y, z.
inline void subtract(double* fx, double* fy, double* fz, std::size_t c0, d4 k, const Geometry& g) {
  store(fx + c0, load(fx + c0) - k * g.q0);
  store(fy + c0, load(fy + c0) - k * g.q1);
  store(fz + c0, load(fz + c0) - k * g.q2);
}
// slot_w += e3 en per lane.
inline void add_energy(double* w, const double* e3, std::size_t c0, d4 en) {
  store(w + c0, load(w + c0) + load(e3 + c0) * en);
}

// The lanes' signed inverse volumes on the stencil path: block c0 of word wc (row bits `row`,
// the word's first entry `word_triple` of inv_volume).
inline d4 stencil_inverse(const LatticeStencil& st, std::uint64_t row, std::size_t word_triple,
                          unsigned s0) {
  const std::uint64_t below = s0 == 0 ? 0 : row & ((std::uint64_t{1} << s0) - 1);
  return expand(&st.inv_volume[word_triple + static_cast<std::size_t>(std::popcount(below))],
                static_cast<unsigned>((row >> s0) & kBatchLanes));
}

// Where a pair's blocks write: the slots' force and energy rows, and the pair's sums and counts.
struct Rows {
  double* fx;
  double* fy;
  double* fz;
  double* w;
  const double* e3;
};
struct Tally {
  double* S;  // [3]
  double& F;
  double& E;
  std::uint64_t& tetrahedra;
  std::uint64_t& inverted;
  bool& any;
};

// The tetrahedra of candidate word wc active for all four vertices (`full`), in blocks of kW
// slots, each starting at the lowest one left. The force forms differ only in the weight:
// `weigh(k, c0)` may rescale the block's f first (energy_consistent: by the mean over the
// vertices) and returns the per-lane factor of the fourth vertex's force (own_family: k3 f;
// energy_consistent: f / V^c). The sets the blocks leave (ill-conditioned or degenerate, general
// path) go to `separate(c, 15)` afterwards with the scalar loop's decisions.
template <class Model, bool kEnergy, bool kPenalty, bool kStencil, class Weigh, class Separate>
inline void book_full_blocks(const Model& model, const Geometry& g, const LatticeStencil* st,
                             std::uint64_t full, std::size_t wc, std::uint64_t triple_word,
                             std::size_t word_triple, double well3, double lo3, const Rows& rows,
                             const Tally& tally, Weigh&& weigh, Separate&& separate) {
  Sums sums;
  std::uint64_t ill_word = 0, tetrahedra = 0, inverted = 0;  // kept local: the loop is hot
  unsigned used = 0;
  while (full) {
    const unsigned s0 = static_cast<unsigned>(std::countr_zero(full));
    const unsigned live = static_cast<unsigned>((full >> s0) & kBatchLanes);
    full &= ~(kBatchLanes << s0);
    const std::size_t c0 = wc * 64 + s0;
    d4 signed_ref;
    if constexpr (kStencil) {
      signed_ref = stencil_inverse(*st, triple_word, word_triple, s0);
    } else {
      signed_ref = g.signed_volume(c0);
    }
    unsigned ill = 0;
    Block k =
        evaluate<Model, kEnergy, kPenalty, kStencil>(model, g, c0, live, signed_ref, well3, ill);
    const d4 factor = weigh(k, c0);
    sums.add(k);
    subtract(rows.fx, rows.fy, rows.fz, c0, factor, g);
    if constexpr (kEnergy) {
      add_energy(rows.w, rows.e3, c0, k.en);
      inverted += static_cast<std::uint64_t>(std::popcount(k.inverted));
    }
    tetrahedra += static_cast<std::uint64_t>(std::popcount(k.use));
    used |= k.use;
    ill_word |= std::uint64_t{ill} << s0;
  }
  sums.into(tally.S, tally.F, tally.E);
  tally.tetrahedra += tetrahedra;
  if constexpr (kEnergy) tally.inverted += inverted;
  tally.any = tally.any || used != 0;
  // As in the scalar loop: the same signed volume, the same decisions.
  for (; ill_word; ill_word &= ill_word - 1) {
    const std::size_t c = wc * 64 + static_cast<std::size_t>(std::countr_zero(ill_word));
    const double V = std::abs(g.R0[0] * g.Rx[c] + g.R1[0] * g.Ry[c] + g.R2[0] * g.Rz[c]);
    if (V >= lo3) separate(c, 15);
  }
}

}  // namespace batch

#endif  // CKPD_BATCHED_TETRAHEDRA

}  // namespace ckpd::symmetric
