#pragma once
// Moving bits between bit rows in order: the bits of a row picked by one mask, put at the bits
// of another mask with as many bits (the first picked bit to the first bit of the second mask,
// and so on). With BMI2 one PEXT and one PDEP per word; a bit at a time otherwise.
#include <bit>
#include <cstddef>
#include <cstdint>

#if defined(__BMI2__)
#include <immintrin.h>
#endif

namespace ckpd {

// The bits of x at the set bits of mask, packed into the low bits (PEXT), a bit at a time.
inline std::uint64_t extract_bits_loop(std::uint64_t x, std::uint64_t mask) {
  std::uint64_t out = 0;
  for (std::uint64_t k = 1; mask != 0; mask &= mask - 1, k <<= 1)
    if (x & mask & (~mask + 1)) out |= k;
  return out;
}

// The low bits of x spread to the set bits of mask (PDEP), a bit at a time.
inline std::uint64_t deposit_bits_loop(std::uint64_t x, std::uint64_t mask) {
  std::uint64_t out = 0;
  for (std::uint64_t k = 1; mask != 0; mask &= mask - 1, k <<= 1)
    if (x & k) out |= mask & (~mask + 1);
  return out;
}

inline std::uint64_t extract_bits(std::uint64_t x, std::uint64_t mask) {
#if defined(__BMI2__)
  return _pext_u64(x, mask);
#else
  return extract_bits_loop(x, mask);
#endif
}

inline std::uint64_t deposit_bits(std::uint64_t x, std::uint64_t mask) {
#if defined(__BMI2__)
  return _pdep_u64(x, mask);
#else
  return deposit_bits_loop(x, mask);
#endif
}

// out = the bits of `from` at the set bits of `pick`, moved in order to the set bits of `put`
// (W words each; pick and put hold as many set bits).
inline void move_bits(const std::uint64_t* from, const std::uint64_t* pick,
                      const std::uint64_t* put, std::size_t W, std::uint64_t* out) {
  // The picked bits, word by word, onto a queue of up to 127 bits in registers; an output word is
  // dealt as soon as the queue holds its count (fewer than 64 wait when a word is added).
  unsigned __int128 queue = 0;
  unsigned held = 0;
  std::size_t w_out = 0;
  auto deal = [&] {
    const unsigned need = static_cast<unsigned>(std::popcount(put[w_out]));
    if (held < need) return false;
    out[w_out] = deposit_bits(static_cast<std::uint64_t>(queue), put[w_out]);
    queue >>= need;
    held -= need;
    ++w_out;
    return true;
  };
  for (std::size_t w = 0; w < W; ++w) {
    queue |= static_cast<unsigned __int128>(extract_bits(from[w], pick[w])) << held;
    held += static_cast<unsigned>(std::popcount(pick[w]));
    while (w_out < W && deal()) {
    }
  }
}

}  // namespace ckpd
