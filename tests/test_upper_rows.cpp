// The general path's adjacency-row table (bodies/upper_rows.hpp): its rows are the definition's
// (bit b of slot a's row set iff a < b and the points of slots a and b are bonded), the kernel
// gives the same forces and energies bit for bit from it as from rows gathered per centre (2D
// and 3D, lattice without stencil and jittered cloud, both damage rules with failed bonds, 1 and
// 2 threads), and a body beyond the memory limit or with another family has none in use.
#include <omp.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <random>
#include <vector>

#include "bodies/body.hpp"
#include "bodies/symmetric_kernel.hpp"
#include "bodies/upper_rows.hpp"
#include "kernel_comparison.hpp"

using ckpd::Body;
using ckpd::DamageRule;
using ckpd::Vec3;

namespace {

const std::vector<kernel_comparison::Scene>& scenes() {
  static const std::vector<kernel_comparison::Scene> all = {
      {"2D lattice, nu=0.4", 2, 0.4, 0.0, 12, 10, 1},
      {"2D jittered cloud, nu=0.3", 2, 0.3, 0.2, 12, 10, 1},
      {"3D lattice, nu=0.3", 3, 0.3, 0.0, 9, 7, 6},
      {"3D jittered cloud", 3, 0.3, 0.2, 9, 7, 6},
  };
  return all;
}

// A body on the general path (the lattice without its stencil), which make_body gives the table.
Body general_body(const kernel_comparison::Scene& s, DamageRule rule, std::mt19937& rng) {
  using namespace kernel_comparison;
  ckpd::BodyDefinition d = block(s.dimension, s.nx, s.ny, s.nz, constants_for(s), s.jitter, rng);
  d.lattice_stencil = false;
  d.damage_rule = rule;
  return ckpd::make_body(std::move(d));
}

bool bonded(const Body& body, std::uint32_t p, std::uint32_t q) {
  const auto first =
      body.family.neighbour.begin() + static_cast<std::ptrdiff_t>(body.family.offset[p]);
  const auto last =
      body.family.neighbour.begin() + static_cast<std::ptrdiff_t>(body.family.offset[p + 1]);
  return std::binary_search(first, last, q);
}

}  // namespace

TEST_CASE("the adjacency-row table holds, for every centre, which upper neighbours are bonded",
          "[upper_rows]") {
  for (const auto& s : scenes()) {
    INFO(s.label);
    std::mt19937 rng(3);
    const Body body = general_body(s, DamageRule::all_edges, rng);
    REQUIRE(body.upper_rows != nullptr);
    const ckpd::UpperRows& rows = *body.upper_rows;
    REQUIRE(rows.matches(body.family));
    std::size_t wrong = 0, bits = 0;
    for (std::size_t i = 0; i < body.size(); ++i) {
      std::vector<std::uint32_t> up;
      for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k)
        if (body.family.neighbour[k] > i) up.push_back(body.family.neighbour[k]);
      const std::size_t m = up.size(), W = (m + 63) / 64;
      REQUIRE(rows.start[i + 1] - rows.start[i] == m * W);
      for (std::size_t a = 0; a < m; ++a)
        for (std::size_t b = 0; b < 64 * W; ++b) {
          const std::uint64_t word = rows.words[rows.start[i] + a * W + b / 64];
          const bool set = (word >> (b % 64)) & 1;
          const bool expected = b < m && a < b && bonded(body, up[a], up[b]);
          wrong += set != expected;
          bits += set;
        }
    }
    CHECK(wrong == 0);
    CHECK(bits > 0);
    CHECK(rows.bytes() == ckpd::upper_rows_bytes(body.family));
  }
}

TEST_CASE(
    "the general path gives the same forces and energies bit for bit from the adjacency-row "
    "table as from rows gathered per centre, with failed bonds",
    "[upper_rows]") {
  kernel_comparison::ThreadCountGuard guard;
  for (const auto& s : scenes())
    for (DamageRule rule : {DamageRule::centre_bonds, DamageRule::all_edges}) {
      std::mt19937 rng(11);
      Body with_table = general_body(s, rule, rng);
      REQUIRE(with_table.upper_rows != nullptr);
      kernel_comparison::perturb(with_table, 0.02, rng);
      kernel_comparison::fail_bonds(with_table, 0.05, rng);
      Body gathered = with_table;
      gathered.upper_rows.reset();
      for (int threads : {1, 2}) {
        omp_set_num_threads(threads);
        INFO(s.label << ", " << ckpd::to_string(rule) << ", " << threads << " threads");
        ckpd::SymmetricKernelWorkspace a, b;
        const auto sa = ckpd::compute_internal_force_symmetric(with_table, true, a);
        const auto sb = ckpd::compute_internal_force_symmetric(gathered, true, b);
        CHECK(sa.tetrahedra + sa.triangles == sb.tetrahedra + sb.triangles);
        CHECK(sa.tetrahedra + sa.triangles > 0);
        CHECK(with_table.force_density == gathered.force_density);
        CHECK(with_table.strain_energy_density == gathered.strain_energy_density);
      }
    }
}

TEST_CASE("no adjacency-row table beyond its memory limit, and none read for another family",
          "[upper_rows]") {
  std::mt19937 rng(4);
  const kernel_comparison::Scene s{"3D jittered cloud", 3, 0.3, 0.2, 9, 7, 6};
  Body body = general_body(s, DamageRule::all_edges, rng);
  const std::size_t bytes = ckpd::upper_rows_bytes(body.family);
  CHECK(ckpd::build_upper_rows(body, bytes - 1) == nullptr);
  CHECK(ckpd::build_upper_rows(body, bytes) != nullptr);
  // A stencil body has none: its rows come from the stencil.
  ckpd::BodyDefinition d =
      kernel_comparison::block(3, 9, 7, 6, kernel_comparison::constants_for(s), 0.0, rng);
  const Body lattice = ckpd::make_body(std::move(d));
  REQUIRE(lattice.stencil != nullptr);
  CHECK(lattice.upper_rows == nullptr);
  // A family with one bond fewer than the table's: the table does not match it.
  ckpd::BondFamily other = body.family;
  other.neighbour.pop_back();
  CHECK_FALSE(body.upper_rows->matches(other));
}
