#pragma once
// Byte flags scanned eight at a time: the positions whose flag differs from the usual value, in
// increasing order. For rows of bond flags (intact, failing) where the exceptions are few.
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace ckpd {

// f(k) for every k in [begin, end) with flag[k] != usual.
template <class Fn>
inline void for_each_flag_other_than(const std::uint8_t* flag, std::size_t begin, std::size_t end,
                                     std::uint8_t usual, Fn&& f) {
  const std::uint64_t usual8 = 0x0101010101010101ull * usual;
  constexpr std::uint64_t low7 = 0x7f7f7f7f7f7f7f7full;
  std::size_t k = begin;
  for (; k + 8 <= end; k += 8) {
    std::uint64_t v;
    std::memcpy(&v, flag + k, sizeof v);
    const std::uint64_t x = v ^ usual8;  // zero bytes where the flag is the usual one
    // The high bit of each nonzero byte of x (no carry crosses a byte: each is 7 bits plus 0x7f).
    for (std::uint64_t other = (((x & low7) + low7) | x) & ~low7; other != 0; other &= other - 1)
      f(k + static_cast<std::size_t>(std::countr_zero(other)) / 8);
  }
  for (; k < end; ++k)
    if (flag[k] != usual) f(k);
}

}  // namespace ckpd
