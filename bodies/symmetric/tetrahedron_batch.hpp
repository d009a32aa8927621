#pragma once
// Vector lanes for the tetrahedra (docs/PERFORMANCE.md, "Tetrahedra in groups of pairs"): 4
// doubles in one 256-bit register (GCC vector extensions), built when the compiler targets AVX2;
// other builds keep the scalar loops (vector extensions without AVX ran 2-3x slower than scalar
// code, docs/PERFORMANCE.md "Batched tetrahedra: a prototype"). Which models take them, the lane
// helpers, and the Seth-Hill measures lane by lane; tetrahedron_group.hpp evaluates the sets.
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
#if defined(CKPD_HAVE_HIGHWAY)
// Highway's vector logarithm and exponentials (static dispatch: the build's own instruction set).
#include <hwy/contrib/math/math-inl.h>
#include <hwy/highway.h>
#endif
#endif

namespace ckpd::symmetric {

// Lanes of the vector helpers below (0: no vector path in this build), and pairs per group of
// tetrahedra (tetrahedron_group.hpp): 8, one AVX-512 register, where the build targets
// AVX-512, else 4; -DCKPD_TETRAHEDRON_GROUP=4 keeps 4 there (measured: docs/PERFORMANCE.md).
#if defined(CKPD_BATCHED_TETRAHEDRA)
inline constexpr int kTetrahedronBatch = 4;
#if defined(__AVX512F__) && !(defined(CKPD_TETRAHEDRON_GROUP) && CKPD_TETRAHEDRON_GROUP == 4)
inline constexpr int kTetrahedronGroup = 8;
#else
inline constexpr int kTetrahedronGroup = 4;
#endif
#else
inline constexpr int kTetrahedronBatch = 0;
inline constexpr int kTetrahedronGroup = 0;
#endif
// The tetrahedron loops are inlined into the pair loop where the groups are built (measured with
// the former blocks: 8-10 % less CPU time per evaluation; the pointer set-up per pair is hoisted).
#if defined(CKPD_BATCHED_TETRAHEDRA)
#define CKPD_TETRAHEDRON_LOOP_INLINE [[gnu::always_inline]]
#else
#define CKPD_TETRAHEDRON_LOOP_INLINE
#endif

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

// Which tetrahedra go in groups: every strain law on both paths. (With the former blocks of 4
// slots the Seth-Hill measures stayed in the scalar loop on the stencil path, 1.3-1.4x faster
// there; the groups of pairs are 2.1x (m = -1/2) and 1.5x (m = 0) faster than that loop:
// docs/PERFORMANCE.md "Seth-Hill tetrahedra in groups on the stencil path".)
template <class Model>
constexpr bool batched_tetrahedra() {
  if constexpr (kTetrahedronBatch > 0 && Model::kTetrahedra && has_strain_law<Model>()) {
    return true;
  } else {
    return false;
  }
}

#if defined(CKPD_BATCHED_TETRAHEDRA)

namespace batch {

constexpr int kW = kTetrahedronBatch;
// Vectors of N doubles (and of N 64-bit integers, the lanes' masks).
template <int N>
struct Vec {
  typedef double d __attribute__((vector_size(8 * N)));
  typedef std::int64_t i __attribute__((vector_size(8 * N)));
};
using d4 = Vec<4>::d;
using i4 = Vec<4>::i;

template <class V>
inline V loadv(const double* p) {
  V v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
template <class V>
inline void storev(double* p, V v) {
  std::memcpy(p, &v, sizeof v);
}
template <class V>
inline V splatv(double x) {
  return V{} + x;
}
inline d4 load(const double* p) {
  return loadv<d4>(p);
}
inline void store(double* p, d4 v) {
  storev(p, v);
}
inline d4 splat(double x) {
  return splatv<d4>(x);
}
// Lane l is all ones where bit l of `bits` is set (I: i4 or Vec<8>::i).
template <class I = i4>
inline I lanes(unsigned bits) {
  I bit;
  for (int l = 0; l < static_cast<int>(sizeof(I) / sizeof(std::int64_t)); ++l)
    bit[l] = std::int64_t{1} << l;
  return ((I{} + static_cast<std::int64_t>(bits)) & bit) != 0;
}
// The lanes of a mask as bits.
inline unsigned bits(i4 mask) {
  return static_cast<unsigned>(_mm256_movemask_pd(reinterpret_cast<__m256d>(mask)));
}
#if defined(__AVX512F__)
inline unsigned bits(Vec<8>::i mask) {
  return static_cast<unsigned>(
      _mm512_cmpneq_epi64_mask(reinterpret_cast<__m512i>(mask), _mm512_setzero_si512()));
}
#endif
// Sum over the lanes, in pairs.
inline double sum(d4 v) {
  return (v[0] + v[1]) + (v[2] + v[3]);
}
#if defined(__AVX512F__)
inline double sum(Vec<8>::d v) {
  return ((v[0] + v[1]) + (v[2] + v[3])) + ((v[4] + v[5]) + (v[6] + v[7]));
}
#endif
// The square root of every lane (correctly rounded, as std::sqrt).
inline d4 lanes_sqrt(d4 v) {
  return reinterpret_cast<d4>(_mm256_sqrt_pd(reinterpret_cast<__m256d>(v)));
}
#if defined(__AVX512F__)
inline Vec<8>::d lanes_sqrt(Vec<8>::d v) {
  // maskz with every lane: the unmasked form trips GCC 12's -Wmaybe-uninitialized.
  return reinterpret_cast<Vec<8>::d>(_mm512_maskz_sqrt_pd(0xFF, reinterpret_cast<__m512d>(v)));
}
#endif
template <class V>
inline V abs(V v) {
  return v < 0 ? -v : v;
}
// sign_of per lane (sign(0) = 0).
template <class V>
inline V sign(V v) {
  const V one = splatv<V>(1.0), zero = splatv<V>(0.0);
  return v > 0 ? one : (v < 0 ? -one : zero);
}

#if defined(CKPD_HAVE_HIGHWAY)
// log(x), log(1 + x), exp(x) - 1 and exp(x) of every lane, by Highway (documented errors: 4, 2, 4
// and 1 ulp). V: Vec<4>::d or Vec<8>::d, the build's widths.
namespace vector_math {
namespace hn = hwy::HWY_NAMESPACE;
template <class V>
using Tag = hn::FixedTag<double, sizeof(V) / sizeof(double)>;
template <class V, class F>
inline V apply(V x, F&& f) {
  alignas(sizeof(V)) double lanes[sizeof(V) / sizeof(double)];
  storev(lanes, x);
  const Tag<V> tag;
  hn::Store(f(tag, hn::Load(tag, lanes)), tag, lanes);
  return loadv<V>(lanes);
}
}  // namespace vector_math
template <class V>
inline V log_lanes(V x) {
  return vector_math::apply(x, [](auto tag, auto v) { return vector_math::hn::Log(tag, v); });
}
template <class V>
inline V log1p_lanes(V x) {
  return vector_math::apply(x, [](auto tag, auto v) { return vector_math::hn::Log1p(tag, v); });
}
template <class V>
inline V expm1_lanes(V x) {
  return vector_math::apply(x, [](auto tag, auto v) { return vector_math::hn::Expm1(tag, v); });
}
template <class V>
inline V exp_lanes(V x) {
  return vector_math::apply(x, [](auto tag, auto v) { return vector_math::hn::Exp(tag, v); });
}
#endif

// The Seth-Hill slope factor e_m(r) r^(2m - 1) and, with kStrain, e_m(r) per lane, from
// d = r - 1, in the order of operations of SethHillStrain::factor and ::strain: m = -1/2 in
// vector arithmetic (one division); any other m with Highway's vector log1p, expm1 and exp where
// the build has it (results within a few ulps of the C library's), else lane by lane with
// SethHillStrain's own functions (no vector forms in the C library without -ffast-math), only in
// the lanes of `use`. Lanes outside `use`, whatever d they hold, get 0 (the caller masks them).
template <bool kStrain, class Strain, class V>
inline void seth_hill_lanes(const Strain& law, V d, unsigned use, V& factor, V& strain) {
  constexpr int N = static_cast<int>(sizeof(V) / sizeof(double));
  if (law.m == -0.5) {
    const V r = splatv<V>(1.0) + d;
    const V ir = splatv<V>(1.0) / r;
    factor = d * ir * ir * ir;
    if constexpr (kStrain) strain = d / r;
    return;
  }
#if defined(CKPD_HAVE_HIGHWAY)
  {
    const auto in_use = lanes<decltype(d < d)>(use);
    // Lanes outside `use` compute from d = 0 (no log of a negative argument there).
    const V du = in_use ? d : splatv<V>(0.0);
    const V lr = log1p_lanes(du);
    V e, f;
    if (law.m == 0) {
      e = lr;
      f = lr / (splatv<V>(1.0) + du);
    } else {
      const double m2 = 2 * law.m;
      e = expm1_lanes(splatv<V>(m2) * lr) / splatv<V>(m2);
      f = e * exp_lanes(splatv<V>(m2 - 1) * lr);
    }
    factor = in_use ? f : splatv<V>(0.0);
    if constexpr (kStrain) strain = in_use ? e : splatv<V>(0.0);
    return;
  }
#endif
  // Lane by lane through plain arrays (element writes would keep the vectors in memory).
  alignas(sizeof(V)) double dl[N], fl[N] = {}, sl[N] = {};
  storev(dl, d);
  for (; use; use &= use - 1) {
    const int l = std::countr_zero(use);
    fl[l] = law.factor(dl[l]);
    if constexpr (kStrain) sl[l] = law.strain(dl[l]);
  }
  factor = loadv<V>(fl);
  if constexpr (kStrain) strain = loadv<V>(sl);
}

}  // namespace batch

#endif  // CKPD_BATCHED_TETRAHEDRA

}  // namespace ckpd::symmetric
