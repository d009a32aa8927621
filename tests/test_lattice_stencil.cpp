// The lattice stencil (bodies/lattice_stencil.hpp) and the symmetric kernel's stencil path:
// which bodies get a stencil and why others do not, and the stencil path against the reference
// kernel (1e-12 of the largest force and energy) and against the general path, on perturbed
// lattice blocks, two-layer plates and cylinders (partial families all around) with randomly
// failed bonds, 2D and 3D, 1 and 2 OpenMP threads.
#include <algorithm>
#include <catch2/catch.hpp>
#include <random>
#include <string>
#include <vector>

#include "bodies/bit_move.hpp"
#include "bodies/body.hpp"
#include "bodies/lattice_stencil.hpp"
#include "bodies/symmetric_kernel.hpp"
#include "kernel_comparison.hpp"

using namespace kernel_comparison;

namespace {

// Keeps the points of a lattice block within the cylinder (2D: disc) along z inscribed in it:
// every point near its curved side has a family that is the stencil minus a different set of
// offsets.
BodyDefinition cut_to_disc(BodyDefinition d) {
  Vec3 lo = d.reference_position.front(), hi = lo;
  for (const Vec3& p : d.reference_position) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Vec3 centre = (lo + hi) / 2;
  const double radius = std::min(hi.x() - lo.x(), hi.y() - lo.y()) / 2 + 1e-9;
  BodyDefinition out = d;
  out.reference_position.clear();
  out.volume.clear();
  for (std::size_t i = 0; i < d.reference_position.size(); ++i) {
    const Vec3 r = d.reference_position[i] - centre;
    if (std::hypot(r.x(), r.y()) <= radius) {
      out.reference_position.push_back(d.reference_position[i]);
      out.volume.push_back(d.volume[i]);
    }
  }
  return out;
}

}  // namespace

TEST_CASE("lattice bodies get a stencil and other point sets say why not", "[lattice_stencil]") {
  std::mt19937 rng(11);
  const Scene s{"3D lattice", 3, 0.3, 0.0, 7, 6, 5};
  const Body lattice = ckpd::make_body(block(3, s.nx, s.ny, s.nz, constants_for(s), 0.0, rng));
  REQUIRE(lattice.stencil);
  CHECK(lattice.stencil_note.empty());
  // m = 3.015: 122 offsets within the horizon, half of them upper.
  CHECK(lattice.stencil->slots == 61);
  CHECK(lattice.stencil->spacing == Approx(kDx).epsilon(1e-12));
  CHECK(lattice.stencil->triples > 0);
  CHECK(lattice.stencil->bytes() < (std::size_t{1} << 20));

  const Body cloud = ckpd::make_body(block(3, s.nx, s.ny, s.nz, constants_for(s), 0.1, rng));
  CHECK_FALSE(cloud.stencil);
  CHECK(cloud.stencil_note.find("not on the lattice") != std::string::npos);

  BodyDefinition reversed = block(3, s.nx, s.ny, s.nz, constants_for(s), 0.0, rng);
  std::reverse(reversed.reference_position.begin(), reversed.reference_position.end());
  const Body backwards = ckpd::make_body(reversed);
  CHECK_FALSE(backwards.stencil);
  CHECK(backwards.stencil_note.find("order") != std::string::npos);

  BodyDefinition off = block(3, s.nx, s.ny, s.nz, constants_for(s), 0.0, rng);
  off.lattice_stencil = false;
  CHECK_FALSE(ckpd::make_body(off).stencil);

  // A two-layer plate at m = 5.015 keeps only the offsets across its thickness.
  const Scene thin{"plate", 3, 0.2, 0.0, 12, 12, 2, false, 5.015};
  const Body plate =
      ckpd::make_body(block(3, thin.nx, thin.ny, thin.nz, constants_for(thin), 0.0, rng, thin.m));
  REQUIRE(plate.stencil);
  int largest_dz = 0;
  for (const auto& o : plate.stencil->offset) largest_dz = std::max(largest_dz, o[2]);
  CHECK(largest_dz == 1);
}

TEST_CASE("a stencil whose tables would exceed the memory limit is not built",
          "[lattice_stencil]") {
  // A few points spanning 7 spacings in x, y and z, m = 7: the stencil's triple table (about
  // m^9) would need far more than the limit.
  BodyDefinition d;
  d.name = "diagonal";
  d.dimension = 3;
  d.density = 1;
  d.horizon = 7 * kDx;
  d.constants = ckpd::interaction_constants(3, kE, 0.3, ckpd::PlaneMode::none, d.horizon);
  d.reference_position = {Vec3(0, 0, 0), Vec3(kDx, 0, 0)};
  for (int k = 1; k <= 7; ++k) d.reference_position.push_back(kDx * Vec3(k, k, k));
  d.volume.assign(d.reference_position.size(), kDx * kDx * kDx);
  d.full_family_volume = static_cast<double>(d.reference_position.size()) * kDx * kDx * kDx;
  const Body body = ckpd::make_body(d);
  CHECK_FALSE(body.stencil);
  CHECK(body.stencil_note.find("MiB") != std::string::npos);
}

TEST_CASE("stencil kernel equals the reference kernel on perturbed, damaged lattice bodies",
          "[lattice_stencil]") {
  ThreadCountGuard guard;
  const std::vector<Scene> scenes = {
      {"2D lattice, plane stress nu=0.2 (C2<0)", 2, 0.2, 0.0, 17, 15, 1},
      {"2D lattice, plane stress nu=0.4 (C2>0)", 2, 0.4, 0.0, 17, 15, 1},
      {"3D lattice, nu=0.3 (C3>0)", 3, 0.3, 0.0, 8, 7, 7},
      {"3D lattice, nu=0.1 (C3<0)", 3, 0.1, 0.0, 8, 7, 7},
      {"3D lattice, triangles and tetrahedra", 3, 0.3, 0.0, 7, 7, 6, true},
      {"2D lattice, m=5.3", 2, 0.4, 0.0, 19, 18, 1, false, 5.3},
      {"3D lattice, m=3.7", 3, 0.3, 0.0, 8, 8, 7, false, 3.7},
      // Thin: only the offsets with |dz| <= 1 are in the stencil (C3 < 0, like the seed's disc).
      {"3D two-layer plate, m=5.015", 3, 0.2, 0.0, 13, 12, 2, false, 5.015},
  };
  std::mt19937 rng(2026);
  for (const Scene& s : scenes) {
    for (const bool disc : {false, true}) {
      for (const double failed : {0.0, 0.15}) {
        DYNAMIC_SECTION(s.label << (disc ? ", disc" : ", block") << ", failed " << failed) {
          BodyDefinition d = block(s.dimension, s.nx, s.ny, s.nz, constants_for(s), 0.0, rng, s.m);
          if (disc) d = cut_to_disc(d);
          Body body = ckpd::make_body(d);
          REQUIRE(body.stencil);
          perturb(body, 0.05, rng);
          if (failed > 0) fail_bonds(body, failed, rng);
          for (const Difference& diff : compare_kernels(body, {1, 2})) {
            INFO("force " << diff.force << ", energy " << diff.energy);
            CHECK(diff.force <= 1e-12);
            CHECK(diff.energy <= 1e-12);
          }
        }
      }
    }
  }
}

// The stencil path's intact rows (symmetric/load_stencil.hpp) move a neighbour's failed upper
// bonds from its own slots to the centre's with move_bits, which needs: sum_inside row a holds
// exactly the slots s whose offset added to a's is a slot, and moving a single slot s from
// sum_inside row a to adjacency row a lands on sum_slot(a, s), the slot of that sum.
TEST_CASE("a neighbour's upper slots move to the centre's slots in order", "[lattice_stencil]") {
  std::mt19937 rng(3);
  for (const Scene& s :
       {Scene{"2D, m=3.015", 2, 0.4, 0.0, 15, 14, 1},
        Scene{"3D, m=3.7", 3, 0.3, 0.0, 8, 8, 7, false, 3.7},
        Scene{"3D two-layer plate, m=5.015", 3, 0.2, 0.0, 13, 12, 2, false, 5.015}}) {
    DYNAMIC_SECTION(s.label) {
      const Body body =
          ckpd::make_body(block(s.dimension, s.nx, s.ny, s.nz, constants_for(s), 0.0, rng, s.m));
      REQUIRE(body.stencil);
      const ckpd::LatticeStencil& st = *body.stencil;
      const std::size_t M = st.slots, W = st.words;
      INFO("slots " << M << ", words " << W);
      std::size_t moved = 0, mismatches = 0;
      for (std::size_t a = 0; a < M; ++a) {
        const std::uint64_t* inside = &st.sum_inside[a * W];
        for (std::size_t t = 0; t < M; ++t) {
          const bool in = (inside[t >> 6] >> (t & 63)) & 1;
          const int b = st.sum_slot(a, t);
          // sum_slot against the offsets themselves.
          bool is_slot = false;
          for (std::size_t c = 0; c < M; ++c)
            if (st.offset[c][0] == st.offset[a][0] + st.offset[t][0] &&
                st.offset[c][1] == st.offset[a][1] + st.offset[t][1] &&
                st.offset[c][2] == st.offset[a][2] + st.offset[t][2]) {
              is_slot = true;
              mismatches += b != static_cast<int>(c);
            }
          mismatches += in != is_slot || (b >= 0) != is_slot;
          if (!in) continue;
          std::vector<std::uint64_t> one(W, 0), out(W, 0);
          one[t >> 6] = std::uint64_t{1} << (t & 63);
          ckpd::move_bits(one.data(), inside, &st.adjacency[a * W], W, out.data());
          std::vector<std::uint64_t> expected(W, 0);
          expected[static_cast<std::size_t>(b) >> 6] = std::uint64_t{1} << (b & 63);
          mismatches += out != expected;
          ++moved;
        }
      }
      CHECK(mismatches == 0);
      CHECK(moved == st.pairs);  // every adjacency bit is the image of one neighbour slot
    }
  }
}

TEST_CASE("stencil path evaluates the same sets as the general path", "[lattice_stencil]") {
  ThreadCountGuard guard;
  std::mt19937 rng(7);
  for (const Scene& s : {Scene{"2D", 2, 0.4, 0.0, 15, 14, 1}, Scene{"3D", 3, 0.3, 0.0, 7, 7, 6},
                         Scene{"3D both", 3, 0.3, 0.0, 6, 6, 6, true}}) {
    DYNAMIC_SECTION(s.label) {
      Body body = ckpd::make_body(
          cut_to_disc(block(s.dimension, s.nx, s.ny, s.nz, constants_for(s), 0.0, rng)));
      REQUIRE(body.stencil);
      perturb(body, 0.05, rng);
      fail_bonds(body, 0.1, rng);
      omp_set_num_threads(2);
      const ckpd::SymmetricKernelStats with = ckpd::compute_internal_force_symmetric(body, true);
      const std::vector<Vec3> force = body.force_density;
      const std::vector<double> energy = body.strain_energy_density;
      Body general = body;
      general.stencil.reset();
      const ckpd::SymmetricKernelStats without =
          ckpd::compute_internal_force_symmetric(general, true);
      CHECK(with.bonds == without.bonds);
      CHECK(with.triangles == without.triangles);
      CHECK(with.tetrahedra == without.tetrahedra);
      CHECK(with.tetrahedra + with.triangles > 0);
      CHECK(without.tetrahedra_per_vertex + without.triangles_per_vertex == 0);
      double scale = 0, diff = 0;
      for (std::size_t i = 0; i < body.size(); ++i) {
        scale = std::max(scale, general.force_density[i].norm());
        diff = std::max(diff, (force[i] - general.force_density[i]).norm());
      }
      CHECK(diff <= 1e-12 * scale);
    }
  }
}

TEST_CASE("stencil and reference differ only by the rounding of the reference positions",
          "[lattice_stencil]") {
  // The stencil takes lengths, areas and volumes from exact lattice offsets, the reference from
  // differences of rounded positions: relative error about eps |X| / dx in the offsets, which
  // the force carries divided by the strain. At 0.5 % strain, a block placed at the origin
  // (|X| / dx <= 26) agrees several times more closely than the same block 430 dx away. (2D, C2 >
  // 0: the triangle terms are the most sensitive.)
  ThreadCountGuard guard;
  omp_set_num_threads(1);
  const Scene s{"2D", 2, 0.4, 0.0, 19, 18, 1};
  double near_origin = 0, far_away = 0;
  for (const bool shifted : {false, true}) {
    std::mt19937 rng(5);
    BodyDefinition d = block(2, s.nx, s.ny, s.nz, constants_for(s), 0.0, rng);
    if (!shifted)
      for (std::size_t i = 0; i < d.reference_position.size(); ++i)
        d.reference_position[i] = kDx * Vec3(double(i % 19), double(i / 19), 0.0);
    Body body = ckpd::make_body(d);
    REQUIRE(body.stencil);
    perturb(body, 0.005, rng);
    (shifted ? far_away : near_origin) = compare_kernels(body, 1).force;
  }
  INFO("at the origin " << near_origin << ", 430 dx away " << far_away);
  CHECK(near_origin <= 5e-13);
  CHECK(far_away > 3 * near_origin);
  CHECK(far_away <= 1e-11);
}
