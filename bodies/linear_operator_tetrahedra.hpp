#pragma once
// One centre's tetrahedra in the linear operator's assembly (linear_operator.hpp), for a model
// whose tetrahedron measure is the volume |v| (Model::kVolumeTetrahedra): a pair (a, b) of
// family slots at a time, vectorised over the thirds d > b. Set by set, each tetrahedron cost
// its whole force term (for the degenerate test), its linearisation and sixteen 3 x 3 rank-one
// updates through the column table; at m = 8 that made 96 % of the far field's set-up
// (issue 20).
//
// With the gradients of |v| at the reference state, up to the set's sign s (which drops out of
// every product g_v g_w^T), G_a = q x r, G_b = r x p, G_d = p x q and G_0 = -(G_a + G_b + G_d)
// (p, q, r the offsets of a, b, d), the set adds -scale_v / V g_v g_w^T to block (v, w) of the
// centre's local rows. scale_v = c_t / row_v with c_t the centre's weight of the set (w3 under
// own_family, V^c w3 / 4 under energy_consistent) and row_v = 1 (own_family) or V^v: so the sum
// over sets S(v, w) = sum c_t / V G_v G_w^T is symmetric, S(w, v) = S(v, w)^T, and is kept
// for v <= w only; the rows' -1 / row_v are applied once per centre when S is added to the
// local blocks. Of the blocks with v < w among the slots 0 < a < b < d, those in column d are
// contiguous over d (one vector store each); those among {0, a, b} are the pair's sums.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "bodies/family_scratch.hpp"

namespace ckpd::linear_operator_detail {

// One thread's sums S of one centre, by slot (0: the centre, 1 + a: family slot a).
struct VolumeTetrahedronBlocks {
  std::size_t m = 0;  // slots
  // Block (v, w), v < w: component 3 i + j (row i, column j) at upper[(3 i + j) m^2 + v m + w].
  std::vector<double> upper;
  // Block (v, v) (symmetric): xx, xy, xz, yy, yz, zz at diagonal[k m + v].
  std::vector<double> diagonal;
  // The family's offsets and lengths by family slot, and one pair's thirds (1: d > b is adjacent
  // to both and the tetrahedron is evaluated; a double, so that the loop's masks are all of one
  // width: a byte flag beside double comparisons kept GCC 12 from vectorising it).
  std::vector<double> x, y, z, length, third;

  // The loop over thirds runs over whole blocks of kLanes (thirds d from b + 1 rounded down to
  // 0 mod kLanes, to n rounded up): no scalar remainders, which took most of the time with the
  // short loops of thin bodies. The lanes outside (b, n) carry no set and add zeros.
  static constexpr std::size_t kLanes = 8;
  static std::size_t lanes_end(std::size_t n) { return (n + kLanes - 1) / kLanes * kLanes; }

  // Zeroed sums for m slots (add_volume_tetrahedra_to_local zeroes what it read); the padding
  // that the last lanes of a row reach only ever receives zeros.
  void prepare(std::size_t slots) {
    m = slots;
    if (upper.size() < 9 * m * m + kLanes) upper.assign(9 * m * m + kLanes, 0.0);
    if (diagonal.size() < 6 * m + kLanes) diagonal.assign(6 * m + kLanes, 0.0);
  }
  double upper_at(int k, std::size_t v, std::size_t w) const {
    return upper[static_cast<std::size_t>(k) * m * m + v * m + w];
  }
  double diagonal_at(int k, std::size_t v) const {
    return diagonal[static_cast<std::size_t>(k) * m + v];
  }
};

// One pair (a, b)'s tetrahedra {0, a, b, d} over its thirds d in [first, n) (n: a multiple of
// kLanes; the lanes from first rounded down to one carry no set): the column-d blocks
// stored, the pair's blocks summed into sums[0..45) ((0, 0) 6, (0, a) 9, (0, b) 9, then without
// only-centre (a, a) 6, (a, b) 9, (b, b) 6). A plain function of restrict pointers: inside the
// pair lambda GCC 12 left the loop scalar. upper/diagonal point at the first plane; A and B are
// the slots of a and b.
struct PairOfTetrahedra {
  double px, py, pz, qx, qy, qz;
  double pair_limit;  // degenerate |P| |Q|: the set is kept where V > pair_limit |R|
  double weight;      // c_t
};
template <bool kOnlyCentre>
inline void tetrahedra_of_pair(const PairOfTetrahedra& pair, std::size_t first, std::size_t n,
                               const double* __restrict x, const double* __restrict y,
                               const double* __restrict z, const double* __restrict length,
                               const double* __restrict third, std::size_t m, std::size_t A,
                               std::size_t B, double* __restrict upper, double* __restrict diagonal,
                               double* __restrict sums) {
  const double px = pair.px, py = pair.py, pz = pair.pz, qx = pair.qx, qy = pair.qy, qz = pair.qz;
  const double pair_limit = pair.pair_limit, weight = pair.weight;
  const double lx = py * qz - pz * qy, ly = pz * qx - px * qz, lz = px * qy - py * qx;  // G_d
  const double llxx = lx * lx, llxy = lx * ly, llxz = lx * lz, llyy = ly * ly, llyz = ly * lz,
               llzz = lz * lz;
  const std::size_t plane = m * m;
  // Row 0, A and B at column 1 + d (slot of third d).
  double* __restrict u0 = upper + 1;
  double* __restrict ua = upper + A * m + 1;
  double* __restrict ub = upper + B * m + 1;
  double* __restrict gd = diagonal + 1;
  // The pair's sums, lane by lane (a loop of fixed length kLanes vectorises whole: with
  // reductions over the loop over thirds GCC's cost model kept the short loops scalar).
  constexpr std::size_t kLanes = VolumeTetrahedronBlocks::kLanes;
  alignas(64) double acc[45][kLanes] = {};
  for (std::size_t base = first / kLanes * kLanes; base < n; base += kLanes) {
    // A block with no third of the pair adds zeros only: passed over. The thirds adjacent to
    // both a and b are a small part of the family, in runs along its rows.
    bool any = false;
    for (std::size_t l = 0; l < kLanes; ++l) any |= (base + l >= first) & (third[base + l] != 0.0);
    if (!any) continue;
#pragma omp simd
    for (std::size_t l = 0; l < kLanes; ++l) {
      const std::size_t d = base + l;
      const double rx = x[d], ry = y[d], rz = z[d];
      const double jx = qy * rz - qz * ry, jy = qz * rx - qx * rz, jz = qx * ry - qy * rx;  // G_a
      const double kx = ry * pz - rz * py, ky = rz * px - rx * pz, kz = rx * py - ry * px;  // G_b
      const double V = std::abs(px * jx + py * jy + pz * jz);
      const bool on = d >= first && third[d] != 0.0 && V > pair_limit * length[d];
      const double kappa = on ? weight / (on ? V : 1.0) : 0.0;
      const double ox = -(jx + kx + lx), oy = -(jy + ky + ly), oz = -(jz + kz + lz);  // G_0
      const double h0x = kappa * ox, h0y = kappa * oy, h0z = kappa * oz;
      // Column d: block (0, d) = kappa G_0 G_d^T.
      u0[d] += h0x * lx;
      u0[plane + d] += h0x * ly;
      u0[2 * plane + d] += h0x * lz;
      u0[3 * plane + d] += h0y * lx;
      u0[4 * plane + d] += h0y * ly;
      u0[5 * plane + d] += h0y * lz;
      u0[6 * plane + d] += h0z * lx;
      u0[7 * plane + d] += h0z * ly;
      u0[8 * plane + d] += h0z * lz;
      acc[0][l] += h0x * ox;
      acc[1][l] += h0x * oy;
      acc[2][l] += h0x * oz;
      acc[3][l] += h0y * oy;
      acc[4][l] += h0y * oz;
      acc[5][l] += h0z * oz;
      acc[6][l] += h0x * jx;
      acc[7][l] += h0x * jy;
      acc[8][l] += h0x * jz;
      acc[9][l] += h0y * jx;
      acc[10][l] += h0y * jy;
      acc[11][l] += h0y * jz;
      acc[12][l] += h0z * jx;
      acc[13][l] += h0z * jy;
      acc[14][l] += h0z * jz;
      acc[15][l] += h0x * kx;
      acc[16][l] += h0x * ky;
      acc[17][l] += h0x * kz;
      acc[18][l] += h0y * kx;
      acc[19][l] += h0y * ky;
      acc[20][l] += h0y * kz;
      acc[21][l] += h0z * kx;
      acc[22][l] += h0z * ky;
      acc[23][l] += h0z * kz;
      if constexpr (!kOnlyCentre) {
        const double hax = kappa * jx, hay = kappa * jy, haz = kappa * jz;
        const double hbx = kappa * kx, hby = kappa * ky, hbz = kappa * kz;
        // Column d: blocks (a, d), (b, d) and (d, d).
        ua[d] += hax * lx;
        ua[plane + d] += hax * ly;
        ua[2 * plane + d] += hax * lz;
        ua[3 * plane + d] += hay * lx;
        ua[4 * plane + d] += hay * ly;
        ua[5 * plane + d] += hay * lz;
        ua[6 * plane + d] += haz * lx;
        ua[7 * plane + d] += haz * ly;
        ua[8 * plane + d] += haz * lz;
        ub[d] += hbx * lx;
        ub[plane + d] += hbx * ly;
        ub[2 * plane + d] += hbx * lz;
        ub[3 * plane + d] += hby * lx;
        ub[4 * plane + d] += hby * ly;
        ub[5 * plane + d] += hby * lz;
        ub[6 * plane + d] += hbz * lx;
        ub[7 * plane + d] += hbz * ly;
        ub[8 * plane + d] += hbz * lz;
        gd[d] += kappa * llxx;
        gd[m + d] += kappa * llxy;
        gd[2 * m + d] += kappa * llxz;
        gd[3 * m + d] += kappa * llyy;
        gd[4 * m + d] += kappa * llyz;
        gd[5 * m + d] += kappa * llzz;
        acc[24][l] += hax * jx;
        acc[25][l] += hax * jy;
        acc[26][l] += hax * jz;
        acc[27][l] += hay * jy;
        acc[28][l] += hay * jz;
        acc[29][l] += haz * jz;
        acc[30][l] += hax * kx;
        acc[31][l] += hax * ky;
        acc[32][l] += hax * kz;
        acc[33][l] += hay * kx;
        acc[34][l] += hay * ky;
        acc[35][l] += hay * kz;
        acc[36][l] += haz * kx;
        acc[37][l] += haz * ky;
        acc[38][l] += haz * kz;
        acc[39][l] += hbx * kx;
        acc[40][l] += hbx * ky;
        acc[41][l] += hbx * kz;
        acc[42][l] += hby * ky;
        acc[43][l] += hby * kz;
        acc[44][l] += hbz * kz;
      }
    }
  }
  for (int k = 0; k < (kOnlyCentre ? 24 : 45); ++k) {
    double sum = 0;
    for (std::size_t l = 0; l < kLanes; ++l) sum += acc[k][l];
    sums[k] = sum;
  }
}

// Adds every tetrahedron of the centre loaded in s to t's sums with the centre's weight c_t
// (above); kOnlyCentre: the sums of row 0 only (own_family). The same sets as for_each_set's
// set-by-set loop (the same degenerate test, multiplied in the same order).
template <bool kOnlyCentre>
inline void accumulate_volume_tetrahedra(const FamilyScratch& s, double degenerate, double weight,
                                         VolumeTetrahedronBlocks& t) {
  const std::size_t n = s.size(), m = n + 1, plane = m * m;
  const std::size_t end = VolumeTetrahedronBlocks::lanes_end(n);
  t.x.assign(end, 0.0);
  t.y.assign(end, 0.0);
  t.z.assign(end, 0.0);
  t.length.assign(end, 0.0);
  t.third.assign(end, 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    t.x[k] = s.ref[k].x();
    t.y[k] = s.ref[k].y();
    t.z[k] = s.ref[k].z();
    t.length[k] = s.length[k];
  }
  double* upper = t.upper.data();
  double* diagonal = t.diagonal.data();
  s.for_each_pair([&](std::size_t a, std::size_t b) {
    if (!s.pair_thirds(a, b, t.third.data())) return;
    const std::size_t A = 1 + a, B = 1 + b;
    const PairOfTetrahedra pair{
        t.x[a], t.y[a], t.z[a], t.x[b], t.y[b], t.z[b], degenerate * t.length[a] * t.length[b],
        weight};
    double sums[45];
    tetrahedra_of_pair<kOnlyCentre>(pair, b + 1, end, t.x.data(), t.y.data(), t.z.data(),
                                    t.length.data(), t.third.data(), m, A, B, upper, diagonal,
                                    sums);
    // The pair's blocks: (0, 0), (0, a), (0, b), and (a, a), (a, b), (b, b).
    for (int k = 0; k < 6; ++k) diagonal[static_cast<std::size_t>(k) * m] += sums[k];
    for (std::size_t k = 0; k < 9; ++k) {
      upper[k * plane + A] += sums[6 + k];
      upper[k * plane + B] += sums[15 + k];
    }
    if constexpr (!kOnlyCentre) {
      for (std::size_t k = 0; k < 6; ++k) {
        diagonal[k * m + A] += sums[24 + k];
        diagonal[k * m + B] += sums[39 + k];
      }
      for (std::size_t k = 0; k < 9; ++k) upper[k * plane + A * m + B] += sums[30 + k];
    }
  });
}

}  // namespace ckpd::linear_operator_detail
