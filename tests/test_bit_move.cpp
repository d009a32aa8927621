// Moving bits between bit rows (bodies/bit_move.hpp): PEXT and PDEP (or their loops) against
// their definitions, and move_bits against placing the picked bits one by one, on random rows of
// one to four words with as many bits picked as put.
#include <catch2/catch.hpp>
#include <cstdint>
#include <random>
#include <vector>

#include "bodies/bit_move.hpp"

namespace {

bool bit_of(const std::vector<std::uint64_t>& row, std::size_t s) {
  return (row[s >> 6] >> (s & 63)) & 1;
}

// A row of W words with `count` bits set at random.
std::vector<std::uint64_t> random_mask(std::size_t W, std::size_t count, std::mt19937_64& rng) {
  std::vector<std::uint64_t> row(W, 0);
  std::uniform_int_distribution<std::size_t> pick(0, 64 * W - 1);
  for (std::size_t set = 0; set < count;) {
    const std::size_t s = pick(rng);
    if (bit_of(row, s)) continue;
    row[s >> 6] |= std::uint64_t{1} << (s & 63);
    ++set;
  }
  return row;
}

}  // namespace

TEST_CASE("extracted and deposited bits follow the masks' set bits in order", "[bit_move]") {
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 2000; ++trial) {
    const std::uint64_t x = rng(), mask = trial % 7 == 0 ? ~std::uint64_t{0} : rng() & rng();
    std::uint64_t extracted = 0, deposited = 0;
    int k = 0;
    for (int s = 0; s < 64; ++s) {
      if (!((mask >> s) & 1)) continue;
      extracted |= ((x >> s) & 1) << k;
      deposited |= ((x >> k) & 1) << s;
      ++k;
    }
    CHECK(ckpd::extract_bits(x, mask) == extracted);
    CHECK(ckpd::extract_bits_loop(x, mask) == extracted);
    CHECK(ckpd::deposit_bits(x, mask) == deposited);
    CHECK(ckpd::deposit_bits_loop(x, mask) == deposited);
  }
}

TEST_CASE("moved bits land on the put mask's bits in the order they were picked", "[bit_move]") {
  std::mt19937_64 rng(5);
  for (std::size_t W = 1; W <= 4; ++W) {
    for (int trial = 0; trial < 500; ++trial) {
      // As many bits picked as put, from none to every bit of the row.
      const std::size_t count = trial == 0 ? 0 : trial == 1 ? 64 * W : rng() % (64 * W + 1);
      const std::vector<std::uint64_t> pick = random_mask(W, count, rng);
      const std::vector<std::uint64_t> put = random_mask(W, count, rng);
      std::vector<std::uint64_t> from(W);
      for (auto& w : from) w = rng();
      std::vector<std::uint64_t> expected(W, 0), out(W, ~std::uint64_t{0});
      std::size_t next = 0;  // the next set bit of put
      for (std::size_t s = 0; s < 64 * W; ++s) {
        if (!bit_of(pick, s)) continue;
        while (!bit_of(put, next)) ++next;
        if (bit_of(from, s)) expected[next >> 6] |= std::uint64_t{1} << (next & 63);
        ++next;
      }
      ckpd::move_bits(from.data(), pick.data(), put.data(), W, out.data());
      INFO("W " << W << ", bits " << count);
      CHECK(out == expected);
    }
  }
}
