#include "bodies/symmetric_kernel.hpp"

#include <omp.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "bodies/family_scratch.hpp"
#include "bodies/lattice_stencil.hpp"

namespace ckpd {

// Scratch of one OpenMP thread. The point being processed is i; its "upper family" is the
// slots a = 0..m-1 holding its neighbours j > i in increasing index order (CSR order), so
// every set enumerated from i has i as its smallest vertex and is seen from no other point.
struct SymmetricKernelThread {
  // This thread's share of the whole-body result, summed over threads in a fixed order.
  std::vector<Vec3> force;
  std::vector<double> energy;

  // Per slot, structure of arrays: global index, reference and current offsets from i.
  std::vector<std::uint32_t> up;
  std::vector<double> Rx, Ry, Rz, rx, ry, rz;
  // Per slot weights: 2 C2 dV2, C2 dV2 / 3, 6 C3 dV3, 3 C3 dV3 / 4 of the slot's point.
  std::vector<double> k2, e2, k3, e3;
  // Per slot accumulators of the force and energy the slot's point receives from i's sets.
  std::vector<double> fx, fy, fz, w;
  // Bit rows, `words` per slot: own = bonds i-slot intact; adj row a = slots b > a that are
  // bonded to a; adj_intact row a = those of them whose bond is intact.
  std::vector<std::uint64_t> own, adj, adj_intact;
  std::size_t m = 0, words = 0;
  // The slots that hold a neighbour, as a bit row and in increasing order (`count` of them):
  // all of 0..m-1 on the general path; on the stencil path, slots are the stencil's upper
  // offsets and those outside the body are absent.
  std::vector<std::uint64_t> present;
  std::vector<std::uint32_t> list;
  std::size_t count = 0;
  // The intact rows are the adjacency rows (no failed bond among i and its upper neighbours).
  bool intact_is_adjacency = false;

  SymmetricKernelStats stats;

  void reserve(std::size_t slots, std::size_t row_words) {
    if (up.size() < slots) {
      for (auto* v : {&Rx, &Ry, &Rz, &rx, &ry, &rz, &k2, &e2, &k3, &e3, &fx, &fy, &fz, &w})
        v->resize(slots);
      up.resize(slots);
      list.resize(slots);
    }
    if (own.size() < row_words) {
      own.resize(row_words);
      present.resize(row_words);
    }
    if (adj.size() < slots * row_words) {
      adj.resize(slots * row_words);
      adj_intact.resize(slots * row_words);
    }
  }
};

SymmetricKernelWorkspace::SymmetricKernelWorkspace() = default;
SymmetricKernelWorkspace::~SymmetricKernelWorkspace() = default;

void SymmetricKernelWorkspace::ensure_threads(std::size_t count) {
  while (threads_.size() < count) threads_.push_back(std::make_unique<SymmetricKernelThread>());
}

namespace {

// Slack on the screens below. The triple product or cross product of the same three or four
// stored points, computed from any vertex in any evaluation order, differs from the exact value
// by at most about 30 ulp of D^3 (D^2): the offsets are correctly rounded differences (relative
// error u per component) and the products add a few u of sum|terms| <= 3 sqrt3 D^3. The screens
// keep 64 eps = 128 u away from any vertex's threshold, so a screened decision is the decision
// every vertex makes; values inside the band are decided exactly, vertex by vertex.
constexpr double kRoundoff = 64 * std::numeric_limits<double>::epsilon();
constexpr double kThresholdSlack = 1e-3;

// Evaluating a set once, with its geometry seen from its first vertex, changes each vertex's
// term by the rounding of |A| or |V| (about eps D^2 or eps D^3): relative to the term, eps D^3/V
// amplified by 1/strain in f = v/|V| - sign v. For slivers (tiny V, which irregular clouds
// have) that exceeds 1e-12 of the largest force, so below these fractions of D^2, D^3 each
// vertex computes its own term exactly as the reference does. Lattices have |V| >= dx^3, about
// D^3/27 at m = 3: they never take the slow path.
// Measured on jittered clouds at 5% strain: 1e-5 leaves differences of 1e-13, 1e-4 and 1e-3
// reach the reference's own noise (1e-14); 1e-3 keeps a margin.
constexpr double kWellConditioned2 = 1e-3;
constexpr double kWellConditioned3 = 1e-3;

struct Context {
  const Body* body = nullptr;
  const Vec3* X = nullptr;
  const Vec3* u = nullptr;  // null when the body has no displacement array
  const std::size_t* offset = nullptr;
  const std::uint32_t* neighbour = nullptr;
  // Null when damage is off: the reference then loads every bond whatever its flag, and so do
  // we (FamilyScratch::load with intact_only = body.damage_enabled).
  const std::uint8_t* intact = nullptr;
  bool pairs = false, triples = false;
  double c1 = 0, c2 = 0, c3 = 0;
  double degenerate = kDegenerateFraction;  // the body's degenerate_fraction
  // Inversion penalty in units of C (2 F |C| / C; 0: off), and whether triangles have an
  // orientation (2D bodies: the z component of the area vector).
  double pen2 = 0, pen3 = 0;
  bool planar = false;
  // |A| > hi2 (|V| > hi3): non-degenerate for every vertex; < lo2 (lo3): degenerate for every
  // vertex; otherwise ask each vertex.
  double hi2 = 0, lo2 = 0, hi3 = 0, lo3 = 0;
  // |A| > well2 (|V| > well3): the set is evaluated once with shared geometry; below, each
  // vertex evaluates its own term with the reference's arithmetic (>= hi2, hi3).
  double well2 = 0, well3 = 0;

  // The body's lattice stencil when the kernel uses it, and then, with damage, one flag per
  // point: some bond of its family has failed.
  const LatticeStencil* stencil = nullptr;
  const std::uint8_t* row_failed = nullptr;

  bool bond_intact(std::size_t k) const { return intact == nullptr || intact[k] != 0; }
  // DamageRule::all_edges with damage on: a set is active for all its vertices or none.
  bool all_edges = false;
};

inline bool bit(const std::uint64_t* row, std::size_t s) {
  return (row[s >> 6] >> (s & 63)) & 1;
}
inline void set_bit(std::uint64_t* row, std::size_t s) {
  row[s >> 6] |= std::uint64_t{1} << (s & 63);
}
// sign(0) = 0 as in the reference. (A branch-free form measured 10% slower on lattices, where
// the orientation of consecutive tetrahedra is well predicted.)
inline double sign(double v) {
  return v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0);
}

// The reference's decisions, reproduced operation for operation (FamilyScratch::load offsets
// X^o - X^c, census_point / evaluate_point products), for vertex c and the other vertices of the
// set in increasing index order, which is the order of c's family slots.
bool triangle_seen(const Vec3* X, double degenerate, std::uint32_t c, std::uint32_t o1,
                   std::uint32_t o2) {
  const Vec3 Xc = X[c];
  const Vec3 P = X[o1] - Xc, Q = X[o2] - Xc;
  const double A = P.cross(Q).norm();
  return A > degenerate * P.norm() * Q.norm();
}

bool tetrahedron_seen(const Vec3* X, double degenerate, std::uint32_t c, std::uint32_t o1,
                      std::uint32_t o2, std::uint32_t o3) {
  const Vec3 Xc = X[c];
  const Vec3 P = X[o1] - Xc, Q = X[o2] - Xc, R = X[o3] - Xc;
  const double V = std::abs(P.dot(Q.cross(R)));
  return V > degenerate * P.norm() * Q.norm() * R.norm();
}

// Bit v set: vertex v (0 = i, 1 = j, 2 = k, 3 = l, indices increasing) counts the set as
// non-degenerate. `size` is |A| or |V| as computed from i.
unsigned triangle_mask(const Context& ctx, double area, std::uint32_t i, std::uint32_t j,
                       std::uint32_t k) {
  if (area > ctx.hi2) return 7;
  if (area < ctx.lo2) return 0;
  const double f = ctx.degenerate;
  return unsigned(triangle_seen(ctx.X, f, i, j, k)) |
         unsigned(triangle_seen(ctx.X, f, j, i, k)) << 1 |
         unsigned(triangle_seen(ctx.X, f, k, i, j)) << 2;
}

unsigned tetrahedron_mask_exact(const Context& ctx, std::uint32_t i, std::uint32_t j,
                                std::uint32_t k, std::uint32_t l) {
  const double f = ctx.degenerate;
  return unsigned(tetrahedron_seen(ctx.X, f, i, j, k, l)) |
         unsigned(tetrahedron_seen(ctx.X, f, j, i, k, l)) << 1 |
         unsigned(tetrahedron_seen(ctx.X, f, k, i, j, l)) << 2 |
         unsigned(tetrahedron_seen(ctx.X, f, l, i, j, k)) << 3;
}

unsigned tetrahedron_mask(const Context& ctx, double volume, std::uint32_t i, std::uint32_t j,
                          std::uint32_t k, std::uint32_t l) {
  if (volume > ctx.hi3) return 15;
  if (volume < ctx.lo3) return 0;
  return tetrahedron_mask_exact(ctx, i, j, k, l);
}

// Slot a of point i's scratch for neighbour j: reference and current offsets (the same
// operations as FamilyScratch::load, so the centre i sees the same numbers), the neighbour's
// weights, and cleared accumulators.
inline void fill_slot(const Context& ctx, SymmetricKernelThread& t, std::size_t a, std::uint32_t j,
                      const Vec3& Xi, const Vec3& ui) {
  const Body& body = *ctx.body;
  const Vec3 R = ctx.X[j] - Xi;
  const Vec3 r = ctx.u ? Vec3(R + (ctx.u[j] - ui)) : R;
  t.Rx[a] = R.x();
  t.Ry[a] = R.y();
  t.Rz[a] = R.z();
  t.rx[a] = r.x();
  t.ry[a] = r.y();
  t.rz[a] = r.z();
  t.k2[a] = 2 * ctx.c2 * body.dv2[j];
  t.e2[a] = ctx.c2 * body.dv2[j] / 3;
  t.k3[a] = 6 * ctx.c3 * body.dv3[j];
  t.e3[a] = 0.75 * ctx.c3 * body.dv3[j];
  t.fx[a] = t.fy[a] = t.fz[a] = t.w[a] = 0;
}

// Rows by merging CSR rows: for each present slot a (in list order) and each later present slot
// b, whether up[b] is in H1(up[a]) (into `adjacency`, when given) and whether that bond is intact
// (into adj_intact), found by merging the two sorted index lists; the bond's intact flag is read
// at the matching CSR position of up[a]'s row.
void merge_csr_rows(const Context& ctx, SymmetricKernelThread& t, std::uint64_t* adjacency) {
  const std::uint32_t* nb = ctx.neighbour;
  const std::size_t W = t.words, count = t.count;
  for (std::size_t n = 0; n < count; ++n) {
    const std::size_t a = t.list[n];
    std::uint64_t* row = adjacency != nullptr ? adjacency + a * W : nullptr;
    std::uint64_t* irow = &t.adj_intact[a * W];
    std::fill_n(irow, W, 0);
    if (row != nullptr) std::fill_n(row, W, 0);
    if (n + 1 == count) break;
    const std::uint32_t j = t.up[a];
    const std::size_t jend = ctx.offset[j + 1];
    std::size_t kk = static_cast<std::size_t>(
        std::upper_bound(nb + ctx.offset[j], nb + jend, t.up[t.list[n + 1]] - 1) - nb);
    std::size_t q = n + 1;
    while (kk < jend && q < count) {
      const std::uint32_t x = nb[kk], y = t.up[t.list[q]];
      if (x == y) {
        if (row != nullptr) set_bit(row, t.list[q]);
        if (ctx.bond_intact(kk)) set_bit(irow, t.list[q]);
        ++kk;
        ++q;
      } else if (x < y) {
        ++kk;
      } else {
        ++q;
      }
    }
  }
}

// Loads point i's upper family into the scratch: offsets, intact bits, per-slot weights and,
// with `rows`, the adjacency between slots. Adjacency comes from the CSR rows, not from
// distances: slot b is in row a iff up[b] is in H1(up[a]), found by merging the two sorted
// index lists, and the bond's intact flag is read at the matching CSR position of up[a]'s row.
// Returns m (0: nothing to do).
std::size_t load_upper_family(const Context& ctx, std::size_t i, SymmetricKernelThread& t,
                              bool rows) {
  const std::uint32_t* nb = ctx.neighbour;
  const std::size_t begin = ctx.offset[i], end = ctx.offset[i + 1];
  const std::size_t first = static_cast<std::size_t>(
      std::upper_bound(nb + begin, nb + end, static_cast<std::uint32_t>(i)) - nb);
  const std::size_t m = end - first;
  t.m = m;
  if (m == 0) return 0;
  const std::size_t W = (m + 63) / 64;
  t.words = W;
  t.reserve(m, W);
  const Vec3 Xi = ctx.X[i];
  const Vec3 ui = ctx.u ? ctx.u[i] : Vec3::Zero();
  std::fill_n(t.own.begin(), W, 0);
  std::fill_n(t.present.begin(), W, ~std::uint64_t{0});
  if (m % 64) t.present[W - 1] = (std::uint64_t{1} << (m % 64)) - 1;
  t.count = m;
  t.intact_is_adjacency = false;
  for (std::size_t a = 0; a < m; ++a) {
    const std::uint32_t j = nb[first + a];
    t.up[a] = j;
    t.list[a] = static_cast<std::uint32_t>(a);
    fill_slot(ctx, t, a, j, Xi, ui);
    if (ctx.bond_intact(first + a)) set_bit(t.own.data(), a);
  }
  if (!rows) return m;
  merge_csr_rows(ctx, t, t.adj.data());
  return m;
}

// The stencil path's load: slots are the stencil's upper offsets; each neighbour j > i of i
// goes to the slot of its lattice offset, with the same offsets, flags and weights as
// load_upper_family. Adjacency rows are the stencil's rows restricted to the present slots;
// intact rows are merged from the CSR rows (as load_upper_family does) only when a bond near i
// has failed. Returns the number of present slots (0: nothing to do).
std::size_t load_upper_family_stencil(const Context& ctx, std::size_t i, SymmetricKernelThread& t,
                                      bool rows) {
  const LatticeStencil& st = *ctx.stencil;
  const std::uint32_t* nb = ctx.neighbour;
  const std::size_t begin = ctx.offset[i], end = ctx.offset[i + 1];
  const std::size_t first = static_cast<std::size_t>(
      std::upper_bound(nb + begin, nb + end, static_cast<std::uint32_t>(i)) - nb);
  const std::size_t count = end - first;
  t.count = count;
  if (count == 0) return 0;
  const std::size_t M = st.slots, W = st.words;
  t.m = M;
  t.words = W;
  t.reserve(M, W);
  const Vec3 Xi = ctx.X[i];
  const Vec3 ui = ctx.u ? ctx.u[i] : Vec3::Zero();
  std::fill_n(t.own.begin(), W, 0);
  std::fill_n(t.present.begin(), W, 0);
  bool failed_near = ctx.row_failed != nullptr && ctx.row_failed[i] != 0;
  for (std::size_t n = 0; n < count; ++n) {
    const std::uint32_t j = nb[first + n];
    const auto a = static_cast<std::size_t>(st.slot(i, j));
    t.up[a] = j;
    t.list[n] = static_cast<std::uint32_t>(a);
    set_bit(t.present.data(), a);
    fill_slot(ctx, t, a, j, Xi, ui);
    if (ctx.bond_intact(first + n)) set_bit(t.own.data(), a);
    if (ctx.row_failed != nullptr) failed_near = failed_near || ctx.row_failed[j] != 0;
  }
  if (!rows) return count;
  const std::uint64_t* present = t.present.data();
  for (std::size_t n = 0; n < count; ++n) {
    const std::size_t a = t.list[n];
    const std::uint64_t* srow = &st.adjacency[a * W];
    std::uint64_t* row = &t.adj[a * W];
    for (std::size_t w = 0; w < W; ++w) row[w] = srow[w] & present[w];
  }
  t.intact_is_adjacency = !failed_near;
  if (failed_near) merge_csr_rows(ctx, t, nullptr);
  return count;
}

// The reference's own term for centre c of a triangle (other vertices o1 < o2) or tetrahedron
// (o1 < o2 < o3), with evaluate_point's arithmetic operation for operation: the path for
// ill-conditioned sets, whose shared-geometry evaluation would differ from the reference by
// more than the tests' 1e-12 (see kWellConditioned). Returns false when c sees the set as
// degenerate. `w` is the term's share of W = W2/3 (W3/4).
bool reference_triangle_term(const Context& ctx, std::uint32_t c, std::uint32_t o1,
                             std::uint32_t o2, Vec3& force, double& w, bool& inverted) {
  const Vec3 Xc = ctx.X[c];
  const Vec3 P = ctx.X[o1] - Xc, Q = ctx.X[o2] - Xc;
  const Vec3 ref_area = P.cross(Q);
  const double A = ref_area.norm();
  if (A <= ctx.degenerate * P.norm() * Q.norm()) return false;
  const Vec3 uc = ctx.u ? ctx.u[c] : Vec3::Zero();
  const Vec3 p = ctx.u ? Vec3(P + (ctx.u[o1] - uc)) : P;
  const Vec3 q = ctx.u ? Vec3(Q + (ctx.u[o2] - uc)) : Q;
  const Vec3 area = p.cross(q);
  const double an = area.norm();
  // The reference's scalar form: (1/A - 1/|a|) a, plus pen2 a/|a| when inverted.
  double f = 1 / A - (an > 0 ? 1 / an : 0.0);
  const double e = an / A - 1;
  double en = A * e * e;
  inverted = ctx.planar && area.z() * ref_area.z() < 0;
  if (inverted) {
    f += ctx.pen2 / an;
    en += 2 * ctx.pen2 * an;
  }
  const double dv2 = ctx.body->dv2[c];
  force = (2 * ctx.c2 * dv2 * f) * (q - p).cross(area);
  w = ctx.c2 * en * dv2 / 3;
  return true;
}

bool reference_tetrahedron_term(const Context& ctx, std::uint32_t c, std::uint32_t o1,
                                std::uint32_t o2, std::uint32_t o3, Vec3& force, double& w,
                                bool& inverted) {
  const Vec3 Xc = ctx.X[c];
  const Vec3 P = ctx.X[o1] - Xc, Q = ctx.X[o2] - Xc, R = ctx.X[o3] - Xc;
  const double signed_V = P.dot(Q.cross(R)), V = std::abs(signed_V);
  if (V <= ctx.degenerate * P.norm() * Q.norm() * R.norm()) return false;
  const Vec3 uc = ctx.u ? ctx.u[c] : Vec3::Zero();
  const Vec3 p = ctx.u ? Vec3(P + (ctx.u[o1] - uc)) : P;
  const Vec3 q = ctx.u ? Vec3(Q + (ctx.u[o2] - uc)) : Q;
  const Vec3 r = ctx.u ? Vec3(R + (ctx.u[o3] - uc)) : R;
  const Vec3 qr = q.cross(r), rp = r.cross(p), pq = p.cross(q);
  const double v = p.dot(qr), av = std::abs(v);
  double factor = v / V - sign(v);
  const double e = av / V - 1;
  double en = V * e * e;
  inverted = v * signed_V < 0;
  if (inverted) {
    factor += ctx.pen3 * sign(v);
    en += 2 * ctx.pen3 * av;
  }
  const double dv3 = ctx.body->dv3[c];
  force = (6 * ctx.c3 * dv3 * factor) * (qr + rp + pq);
  w = 3 * ctx.c3 * en * dv3 / 4;
  return true;
}

// Force and energy from i's bonds, triangles and tetrahedra, added to thread t's arrays. With
// kEnergy the inverted sets are counted; with kPenalty they get the inversion penalty.
// With kStencil, point i's slots and reference geometry come from the body's lattice stencil.
template <bool kEnergy, bool kPenalty, bool kStencil>
void process_point(const Context& ctx, std::size_t i, SymmetricKernelThread& t) {
  const bool rows = ctx.pairs || ctx.triples;
  const std::size_t count =
      kStencil ? load_upper_family_stencil(ctx, i, t, rows) : load_upper_family(ctx, i, t, rows);
  if (count == 0) return;
  const LatticeStencil* st = ctx.stencil;
  const std::uint32_t* list = t.list.data();
  const std::uint64_t* present = t.present.data();
  const Body& body = *ctx.body;
  const std::size_t W = t.words;
  const std::uint64_t* own = t.own.data();
  const auto ii = static_cast<std::uint32_t>(i);
  // Raw views of the scratch: stores through them cannot be taken for changes to the vectors
  // themselves, so the base pointers stay in registers in the inner loops.
  const std::uint32_t* __restrict up = t.up.data();
  const double* __restrict Rx = t.Rx.data();
  const double* __restrict Ry = t.Ry.data();
  const double* __restrict Rz = t.Rz.data();
  const double* __restrict rx = t.rx.data();
  const double* __restrict ry = t.ry.data();
  const double* __restrict rz = t.rz.data();
  const double* __restrict k2 = t.k2.data();
  const double* __restrict e2 = t.e2.data();
  const double* __restrict k3 = t.k3.data();
  const double* __restrict e3 = t.e3.data();
  double* __restrict fx = t.fx.data();
  double* __restrict fy = t.fy.data();
  double* __restrict fz = t.fz.data();
  double* __restrict slot_w = t.w.data();
  std::uint64_t n_bonds = 0, n_triangles = 0, n_tetrahedra = 0;
  std::uint64_t n_triangles_per_vertex = 0, n_tetrahedra_per_vertex = 0;
  std::uint64_t n_inverted_triangles = 0, n_inverted_tetrahedra = 0;
  double fix = 0, fiy = 0, fiz = 0, wi = 0;
  // Adds a per-vertex term to vertex 0 (i) or to a slot.
  auto add = [&](std::size_t slot, bool is_i, const Vec3& f, double w) {
    if (is_i) {
      fix += f.x();
      fiy += f.y();
      fiz += f.z();
      if constexpr (kEnergy) wi += w;
    } else {
      fx[slot] += f.x();
      fy[slot] += f.y();
      fz[slot] += f.z();
      if constexpr (kEnergy) slot_w[slot] += w;
    }
  };

  // Bonds {i, j}: d1 is the same from both ends, and dx^ji = -dx^ij exactly.
  {
    const double dv1i = body.dv1[i];
    for (std::size_t wd = 0; wd < W; ++wd) {
      for (std::uint64_t bits = own[wd]; bits; bits &= bits - 1) {
        const std::size_t a = wd * 64 + static_cast<std::size_t>(std::countr_zero(bits));
        double L, inv_L;
        if constexpr (kStencil) {
          L = st->length[a];
          inv_L = st->inv_length[a];
        } else {
          L = std::sqrt(Rx[a] * Rx[a] + Ry[a] * Ry[a] + Rz[a] * Rz[a]);
          inv_L = 1 / L;
        }
        const double l = std::sqrt(rx[a] * rx[a] + ry[a] * ry[a] + rz[a] * rz[a]);
        const double k = ctx.c1 * (inv_L - 1 / l);
        const double dv1j = body.dv1[up[a]];
        fix += k * dv1i * rx[a];
        fiy += k * dv1i * ry[a];
        fiz += k * dv1i * rz[a];
        fx[a] -= k * dv1j * rx[a];
        fy[a] -= k * dv1j * ry[a];
        fz[a] -= k * dv1j * rz[a];
        if constexpr (kEnergy) {
          const double s = l / L - 1;
          const double e = 0.25 * ctx.c1 * L * s * s;  // psi1 / 2: W = W1 / 2
          wi += e * dv1i;
          slot_w[a] += e * dv1j;
        }
        ++n_bonds;
      }
    }
  }

  const double k2i = 2 * ctx.c2 * body.dv2[i], e2i = ctx.c2 * body.dv2[i] / 3;
  const double k3i = 6 * ctx.c3 * body.dv3[i], e3i = 0.75 * ctx.c3 * body.dv3[i];

  for (std::size_t n = 0; n < count && rows; ++n) {
    const std::size_t a = list[n];
    const std::uint64_t* ra = &t.adj[a * W];
    const std::uint64_t* ia = t.intact_is_adjacency ? ra : &t.adj_intact[a * W];
    // Stencil path: pair (a, b) is number pair_base[a] + the rank of b in a's stencil row.
    std::size_t pair_rank = kStencil ? st->pair_base[a] : 0;
    const bool own_a = bit(own, a);
    const double Pa[3] = {Rx[a], Ry[a], Rz[a]};
    const double pa[3] = {rx[a], ry[a], rz[a]};
    for (std::size_t wb = a >> 6; wb < W; ++wb) {
      std::uint64_t stencil_row = 0;
      std::size_t word_rank = 0;
      if constexpr (kStencil) {
        stencil_row = st->adjacency[a * W + wb];
        word_rank = pair_rank;
        pair_rank += static_cast<std::size_t>(std::popcount(stencil_row));
      }
      for (std::uint64_t bbits = ra[wb]; bbits; bbits &= bbits - 1) {
        const std::size_t b = wb * 64 + static_cast<std::size_t>(std::countr_zero(bbits));
        const std::size_t pair =
            kStencil ? word_rank + static_cast<std::size_t>(std::popcount(
                                       stencil_row & ((std::uint64_t{1} << (b & 63)) - 1)))
                     : 0;
        const bool own_b = bit(own, b), bond_ab = bit(ia, b);
        // Which vertices have both (all) of their bonds in the set intact (d2, d3); under
        // all_edges, every vertex needs all three edges of the triangle intact.
        const bool edges_ab = own_a && own_b && bond_ab;
        const bool act_i = ctx.all_edges ? edges_ab : own_a && own_b;
        const bool act_j = ctx.all_edges ? edges_ab : own_a && bond_ab;
        const bool act_k = ctx.all_edges ? edges_ab : own_b && bond_ab;
        const double Pb[3] = {Rx[b], Ry[b], Rz[b]};
        const double pb[3] = {rx[b], ry[b], rz[b]};
        // Reference and current cross products of the (a, b) edge pair: the triangle's area
        // vector and, for tetrahedra, the gradient of v at the fourth vertex.
        // (Not needed on the stencil path, which has the pair's and its triples' numbers.)
        const double RPQ[3] = {Pa[1] * Pb[2] - Pa[2] * Pb[1], Pa[2] * Pb[0] - Pa[0] * Pb[2],
                               Pa[0] * Pb[1] - Pa[1] * Pb[0]};
        const double pq[3] = {pa[1] * pb[2] - pa[2] * pb[1], pa[2] * pb[0] - pa[0] * pb[2],
                              pa[0] * pb[1] - pa[1] * pb[0]};

        if (ctx.pairs && (act_i || act_j || act_k)) {
          // Stencil: 1/A from the table, 0 for a degenerate (collinear) pair, and a lattice's
          // sets are never ill-conditioned. General: A from the reference offsets.
          double A = 0, inv_A = 0, ref_z = 0;
          if constexpr (kStencil) {
            inv_A = st->inv_area[pair];
            ref_z = st->area_z[pair];
          } else {
            A = std::sqrt(RPQ[0] * RPQ[0] + RPQ[1] * RPQ[1] + RPQ[2] * RPQ[2]);
            ref_z = RPQ[2];
          }
          const unsigned active = unsigned(act_i) | unsigned(act_j) << 1 | unsigned(act_k) << 2;
          if (kStencil ? inv_A != 0 : A > ctx.well2) {
            const double an = std::sqrt(pq[0] * pq[0] + pq[1] * pq[1] + pq[2] * pq[2]);
            // (1/A - 1/|a|) a, finite for a collapsed triangle (as in the reference).
            double fa = (kStencil ? inv_A : 1 / A) - (an > 0 ? 1 / an : 0.0);
            const double e = kStencil ? an * inv_A - 1 : an / A - 1;
            double en = kStencil ? e * e / inv_A : A * e * e;
            if constexpr (kEnergy || kPenalty) {
              if (ctx.planar && pq[2] * ref_z < 0) {  // inverted (2D: orientation is z)
                if constexpr (kEnergy) ++n_inverted_triangles;
                if constexpr (kPenalty) {
                  fa += ctx.pen2 / an;
                  en += 2 * ctx.pen2 * an;
                }
              }
            }
            double g[3];
            for (int d = 0; d < 3; ++d) g[d] = fa * pq[d];
            // d|a|/dx^c = G_c x n with G_i = p - q, G_j = q, G_k = -p, and
            // -2 C2 dV2 (|a|/A - 1) G_c x n = -2 C2 dV2 G_c x g.
            if (active & 1) {
              const double qp[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
              fix += k2i * (qp[1] * g[2] - qp[2] * g[1]);
              fiy += k2i * (qp[2] * g[0] - qp[0] * g[2]);
              fiz += k2i * (qp[0] * g[1] - qp[1] * g[0]);
              if constexpr (kEnergy) wi += e2i * en;
            }
            if (active & 2) {
              fx[a] -= k2[a] * (pb[1] * g[2] - pb[2] * g[1]);
              fy[a] -= k2[a] * (pb[2] * g[0] - pb[0] * g[2]);
              fz[a] -= k2[a] * (pb[0] * g[1] - pb[1] * g[0]);
              if constexpr (kEnergy) slot_w[a] += e2[a] * en;
            }
            if (active & 4) {
              fx[b] += k2[b] * (pa[1] * g[2] - pa[2] * g[1]);
              fy[b] += k2[b] * (pa[2] * g[0] - pa[0] * g[2]);
              fz[b] += k2[b] * (pa[0] * g[1] - pa[1] * g[0]);
              if constexpr (kEnergy) slot_w[b] += e2[b] * en;
            }
            ++n_triangles;
          } else if (!kStencil && A >= ctx.lo2) {
            // Ill-conditioned or near the degeneracy threshold: each vertex on its own.
            const std::uint32_t vj = up[a], vk = up[b];
            Vec3 f;
            double w = 0;
            bool seen = false, inverted = false, inv = false;
            if ((active & 1) && reference_triangle_term(ctx, ii, vj, vk, f, w, inv)) {
              add(0, true, f, w);
              seen = true;
              inverted |= inv;
            }
            if ((active & 2) && reference_triangle_term(ctx, vj, ii, vk, f, w, inv)) {
              add(a, false, f, w);
              seen = true;
              inverted |= inv;
            }
            if ((active & 4) && reference_triangle_term(ctx, vk, ii, vj, f, w, inv)) {
              add(b, false, f, w);
              seen = true;
              inverted |= inv;
            }
            if constexpr (kEnergy) n_inverted_triangles += inverted;
            n_triangles += seen;
            n_triangles_per_vertex += seen;
          }
        }

        if (!ctx.triples) continue;
        // Tetrahedra {i, a, b, c}: c > b bonded to both a and b (and to i: every slot is).
        // With p, q, r the current offsets to a, b, c and v = p.(q x r), the gradients are
        // g_j = q x r, g_k = r x p, g_l = p x q, g_i = -(g_j + g_k + g_l), and each vertex
        // gets -6 C3 dV3 f g with f = v/|V| - sign v. Summed over c at fixed (a, b), the
        // forces on i, j, k need only S = sum f r and F = sum f (the cross products are
        // linear), so the per-tetrahedron work is two dot products, one division and the
        // fourth vertex's force. Sums with all four vertices active go to (S, F, E); sums for
        // partially active sets to per-vertex accumulators.
        const std::uint64_t* rb = &t.adj[b * W];
        const std::uint64_t* ib = t.intact_is_adjacency ? rb : &t.adj_intact[b * W];
        double S[3] = {0, 0, 0}, F = 0, E = 0;
        double Si[3] = {0, 0, 0}, Fi = 0, Ei = 0;
        // j and k need no F: their gradients q x r and r x p are linear in r alone.
        double Sj[3] = {0, 0, 0}, Ej = 0;
        double Sk[3] = {0, 0, 0}, Ek = 0;
        bool any = false;
        // A well-conditioned tetrahedron with some vertices inactive: vertex by vertex.
        auto partial = [&](std::size_t c, unsigned mask, double signed_V) {
          const double V = std::abs(signed_V);
          const double r[3] = {rx[c], ry[c], rz[c]};
          const double v = pq[0] * r[0] + pq[1] * r[1] + pq[2] * r[2];
          double f = v / V - sign(v);
          double en = 0;
          if constexpr (kEnergy) {
            const double e = std::abs(v) / V - 1;
            en = V * e * e;
          }
          if constexpr (kEnergy || kPenalty) {
            if (v * signed_V < 0) {
              if constexpr (kEnergy) ++n_inverted_tetrahedra;
              if constexpr (kPenalty) {
                f += ctx.pen3 * sign(v);
                if constexpr (kEnergy) en += 2 * ctx.pen3 * std::abs(v);
              }
            }
          }
          if (mask & 1) {
            for (int d = 0; d < 3; ++d) Si[d] += f * r[d];
            Fi += f;
            Ei += en;
          }
          if (mask & 2) {
            for (int d = 0; d < 3; ++d) Sj[d] += f * r[d];
            Ej += en;
          }
          if (mask & 4) {
            for (int d = 0; d < 3; ++d) Sk[d] += f * r[d];
            Ek += en;
          }
          if (mask & 8) {
            const double kl = k3[c] * f;
            fx[c] -= kl * pq[0];
            fy[c] -= kl * pq[1];
            fz[c] -= kl * pq[2];
            if constexpr (kEnergy) slot_w[c] += e3[c] * en;
          }
          any = true;
          ++n_tetrahedra;
        };
        // An ill-conditioned tetrahedron (or one near the degeneracy threshold): each active
        // vertex decides and evaluates its own term as the reference does.
        auto separate = [&](std::size_t c, unsigned active) {
          const std::uint32_t vj = up[a], vk = up[b], vl = up[c];
          Vec3 f;
          double w = 0;
          bool seen = false, inverted = false, inv = false;
          if ((active & 1) && reference_tetrahedron_term(ctx, ii, vj, vk, vl, f, w, inv)) {
            add(0, true, f, w);
            seen = true;
            inverted |= inv;
          }
          if ((active & 2) && reference_tetrahedron_term(ctx, vj, ii, vk, vl, f, w, inv)) {
            add(a, false, f, w);
            seen = true;
            inverted |= inv;
          }
          if ((active & 4) && reference_tetrahedron_term(ctx, vk, ii, vj, vl, f, w, inv)) {
            add(b, false, f, w);
            seen = true;
            inverted |= inv;
          }
          if ((active & 8) && reference_tetrahedron_term(ctx, vl, ii, vj, vk, f, w, inv)) {
            add(c, false, f, w);
            seen = true;
            inverted |= inv;
          }
          if constexpr (kEnergy) n_inverted_tetrahedra += inverted;
          n_tetrahedra += seen;
          n_tetrahedra_per_vertex += seen;
        };
        // Stencil path: the pair's row of non-degenerate triples; triple (a, b, c) is number
        // triple_base[pair] + the rank of c in that row, and its entry is 1 / V.
        const std::uint64_t* triple_row = kStencil ? &st->triple_row[pair * W] : nullptr;
        std::size_t triple_rank = kStencil ? st->triple_base[pair] : 0;
        for (std::size_t wc = b >> 6; wc < W; ++wc) {
          std::uint64_t cand;
          std::size_t word_triple = 0;
          if constexpr (kStencil) {
            const std::uint64_t tr = triple_row[wc];
            cand = tr & present[wc];
            word_triple = triple_rank;
            triple_rank += static_cast<std::size_t>(std::popcount(tr));
          } else {
            cand = ra[wc] & rb[wc];
          }
          if (!cand) continue;
          // 1 / V of triple c, whose bit is in word wc (stencil path only).
          auto inv_volume = [&](std::size_t c) {
            return st->inv_volume[word_triple +
                                  static_cast<std::size_t>(std::popcount(
                                      triple_row[wc] & ((std::uint64_t{1} << (c & 63)) - 1)))];
          };
          // Per vertex, the c whose tetrahedron it sees with its three bonds intact. Under
          // all_edges all six edges must be intact (i's three, a-b, a-c, b-c), for every vertex.
          const std::uint64_t ml = ctx.all_edges && !edges_ab ? 0 : own[wc] & ia[wc] & ib[wc];
          std::uint64_t mi = act_i ? own[wc] : 0, mj = act_j ? ia[wc] : 0, mk = act_k ? ib[wc] : 0;
          if (ctx.all_edges) mi = mj = mk = ml;
          std::uint64_t full = cand & mi & mj & mk & ml;
          std::uint64_t part = cand & (mi | mj | mk | ml) & ~full;
          for (; full; full &= full - 1) {
            const std::size_t c = wc * 64 + static_cast<std::size_t>(std::countr_zero(full));
            // signed_V: the signed reference volume (general path) or its inverse (stencil);
            // only its sign is used below besides V or 1/V.
            double signed_V, V, inv_V;
            if constexpr (kStencil) {
              signed_V = inv_volume(c);
              inv_V = std::abs(signed_V);
              V = 0;
            } else {
              signed_V = RPQ[0] * Rx[c] + RPQ[1] * Ry[c] + RPQ[2] * Rz[c];
              V = std::abs(signed_V);
              inv_V = 0;
              if (!(V > ctx.well3)) {  // rare on lattices; degenerate sets end here
                if (V >= ctx.lo3) separate(c, 15);
                continue;
              }
            }
            const double r[3] = {rx[c], ry[c], rz[c]};
            const double v = pq[0] * r[0] + pq[1] * r[1] + pq[2] * r[2];
            double f = kStencil ? v * inv_V - sign(v) : v / V - sign(v);
            double pen_en = 0;  // the penalty's share of the energy, V e^2 units
            if constexpr (kEnergy || kPenalty) {
              if (v * signed_V < 0) {
                if constexpr (kEnergy) ++n_inverted_tetrahedra;
                if constexpr (kPenalty) {
                  f += ctx.pen3 * sign(v);
                  pen_en = 2 * ctx.pen3 * std::abs(v);
                }
              }
            }
            S[0] += f * r[0];
            S[1] += f * r[1];
            S[2] += f * r[2];
            F += f;
            const double kl = k3[c] * f;
            fx[c] -= kl * pq[0];
            fy[c] -= kl * pq[1];
            fz[c] -= kl * pq[2];
            if constexpr (kEnergy) {
              const double e = kStencil ? std::abs(v) * inv_V - 1 : std::abs(v) / V - 1;
              const double en = (kStencil ? e * e / inv_V : V * e * e) + pen_en;
              E += en;
              slot_w[c] += e3[c] * en;
            }
            any = true;
            ++n_tetrahedra;
          }
          for (; part; part &= part - 1) {
            const std::size_t c = wc * 64 + static_cast<std::size_t>(std::countr_zero(part));
            const double signed_V =
                kStencil ? 1 / inv_volume(c) : RPQ[0] * Rx[c] + RPQ[1] * Ry[c] + RPQ[2] * Rz[c];
            const double V = std::abs(signed_V);
            const unsigned active =
                unsigned((mi >> (c & 63)) & 1) | unsigned((mj >> (c & 63)) & 1) << 1 |
                unsigned((mk >> (c & 63)) & 1) << 2 | unsigned((ml >> (c & 63)) & 1) << 3;
            if (kStencil || V > ctx.well3) {
              partial(c, active, signed_V);
            } else if (V >= ctx.lo3) {
              separate(c, active);
            }
          }
        }
        if (!any) continue;
        // i: +6 C3 dV3 sum f (q x r + r x p + p x q) = 6 C3 dV3 ((q - p) x S + (p x q) F).
        {
          const double s[3] = {S[0] + Si[0], S[1] + Si[1], S[2] + Si[2]};
          const double fs = F + Fi;
          const double qp[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
          fix += k3i * (qp[1] * s[2] - qp[2] * s[1] + pq[0] * fs);
          fiy += k3i * (qp[2] * s[0] - qp[0] * s[2] + pq[1] * fs);
          fiz += k3i * (qp[0] * s[1] - qp[1] * s[0] + pq[2] * fs);
          if constexpr (kEnergy) wi += e3i * (E + Ei);
        }
        // j (slot a): -6 C3 dV3 q x S.
        {
          const double s[3] = {S[0] + Sj[0], S[1] + Sj[1], S[2] + Sj[2]};
          fx[a] -= k3[a] * (pb[1] * s[2] - pb[2] * s[1]);
          fy[a] -= k3[a] * (pb[2] * s[0] - pb[0] * s[2]);
          fz[a] -= k3[a] * (pb[0] * s[1] - pb[1] * s[0]);
          if constexpr (kEnergy) slot_w[a] += e3[a] * (E + Ej);
        }
        // k (slot b): -6 C3 dV3 S x p.
        {
          const double s[3] = {S[0] + Sk[0], S[1] + Sk[1], S[2] + Sk[2]};
          fx[b] -= k3[b] * (s[1] * pa[2] - s[2] * pa[1]);
          fy[b] -= k3[b] * (s[2] * pa[0] - s[0] * pa[2]);
          fz[b] -= k3[b] * (s[0] * pa[1] - s[1] * pa[0]);
          if constexpr (kEnergy) slot_w[b] += e3[b] * (E + Ek);
        }
      }
    }
  }

  t.stats.bonds += n_bonds;
  t.stats.triangles += n_triangles;
  t.stats.tetrahedra += n_tetrahedra;
  t.stats.triangles_per_vertex += n_triangles_per_vertex;
  t.stats.tetrahedra_per_vertex += n_tetrahedra_per_vertex;
  t.stats.inverted_triangles += n_inverted_triangles;
  t.stats.inverted_tetrahedra += n_inverted_tetrahedra;
  // Flush: i's own sum and every slot's share into this thread's whole-body arrays.
  t.force[i] += Vec3(fix, fiy, fiz);
  if constexpr (kEnergy) t.energy[i] += wi;
  for (std::size_t n = 0; n < count; ++n) {
    const std::size_t a = list[n];
    t.force[up[a]] += Vec3(fx[a], fy[a], fz[a]);
    if constexpr (kEnergy) t.energy[up[a]] += slot_w[a];
  }
}

Context make_context(const Body& body) {
  Context ctx;
  ctx.body = &body;
  ctx.X = body.reference_position.data();
  ctx.u = body.displacement.empty() ? nullptr : body.displacement.data();
  ctx.offset = body.family.offset.data();
  ctx.neighbour = body.family.neighbour.data();
  ctx.intact = body.damage_enabled ? body.bond_intact.data() : nullptr;
  ctx.all_edges = ctx.intact != nullptr && body.damage_rule == DamageRule::all_edges;
  ctx.pairs = body.has_pairs();
  ctx.triples = body.has_triples();
  ctx.c1 = body.constants.c1;
  ctx.c2 = body.constants.c2;
  ctx.c3 = body.constants.c3;
  ctx.degenerate = body.degenerate_fraction;
  const double F = body.inversion_penalty;
  ctx.pen2 = ctx.c2 != 0 ? 2 * F * (ctx.c2 > 0 ? 1.0 : -1.0) : 0.0;
  ctx.pen3 = ctx.c3 != 0 ? 2 * F * (ctx.c3 > 0 ? 1.0 : -1.0) : 0.0;
  ctx.planar = body.dimension == 2;
  return ctx;
}

// Screens from the largest possible edge (the horizon) and the shortest bond in the body.
void set_screens(Context& ctx, double min_bond_length) {
  const double D = ctx.body->horizon * (1 + kHorizonTolerance);
  const double D2 = D * D, D3 = D2 * D;
  const double L2 = min_bond_length * min_bond_length, L3 = L2 * min_bond_length;
  const double f = ctx.degenerate;
  ctx.hi2 = f * (1 + kThresholdSlack) * D2 + kRoundoff * D2;
  ctx.hi3 = f * (1 + kThresholdSlack) * D3 + kRoundoff * D3;
  ctx.lo2 = f * (1 - kThresholdSlack) * L2 - kRoundoff * D2;
  ctx.lo3 = f * (1 - kThresholdSlack) * L3 - kRoundoff * D3;
  ctx.well2 = std::max(ctx.hi2, kWellConditioned2 * D2);
  ctx.well3 = std::max(ctx.hi3, kWellConditioned3 * D3);
}

double squared_length(const Body& body, std::size_t i, std::size_t k) {
  return (body.reference_position[body.family.neighbour[k]] - body.reference_position[i])
      .squaredNorm();
}

}  // namespace

bool uses_lattice_stencil(const Body& body) {
  // The stencil serves only the interaction families it was built with (the constants set
  // which; they do not change sign after the body is made, but a caller may zero one). Bond-only
  // bodies keep the general path: the slot look-up costs more than the 1/L it saves (measured
  // 0.87x on a 24^3 block, nu = 0.25; docs/PERFORMANCE.md).
  const LatticeStencil* st = body.stencil.get();
  const bool pairs = body.has_pairs(), triples = body.has_triples();
  return st != nullptr && (pairs || triples) && (!pairs || !st->inv_area.empty()) &&
         (!triples || !st->triple_row.empty()) && !st->adjacency.empty();
}

SymmetricKernelStats compute_internal_force_symmetric(Body& body, bool with_energy,
                                                      SymmetricKernelWorkspace& workspace) {
  const std::size_t n = body.size();
  Context ctx = make_context(body);
  workspace.ensure_threads(static_cast<std::size_t>(std::max(1, omp_get_max_threads())));
  if (uses_lattice_stencil(body)) {
    const LatticeStencil* st = body.stencil.get();
    ctx.stencil = st;
    if (ctx.intact != nullptr) {
      if (workspace.row_failed.size() < n) workspace.row_failed.resize(n);
      ctx.row_failed = workspace.row_failed.data();
    }
  }
  double min_length2 = std::numeric_limits<double>::infinity();
  int team = 1;
  // Static schedule: which thread handles which point is a function of the thread count only,
  // so each thread's partial sums, and their sum in thread order, are reproducible. Chunks of 64
  // interleave the threads finely enough to spread the cheap points (few upper neighbours: the
  // high-index surface); measured on a 20^3 block with 2 threads: chunks of 16 scaled 1.85x,
  // 64 to 256 1.95x (consecutive points write to overlapping neighbours: better locality).
  constexpr int kChunk = 64;
#pragma omp parallel
  {
    const std::size_t t = static_cast<std::size_t>(omp_get_thread_num());
#pragma omp single
    team = omp_get_num_threads();
    SymmetricKernelThread& th = workspace.thread(t);
    th.stats = {};
    th.force.assign(n, Vec3::Zero());  // keeps its capacity: no allocation after the first call
    if (with_energy) th.energy.assign(n, 0.0);
    if (ctx.pairs || ctx.triples) {
#pragma omp for schedule(static) reduction(min : min_length2)
      for (std::size_t i = 0; i < n; ++i)
        for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k)
          min_length2 = std::min(min_length2, squared_length(body, i, k));
#pragma omp single
      set_screens(ctx, std::sqrt(min_length2));
    }
    if (ctx.stencil != nullptr && ctx.intact != nullptr) {
#pragma omp for schedule(static)
      for (std::size_t i = 0; i < n; ++i) {
        std::uint8_t failed = 0;
        for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k)
          failed |= static_cast<std::uint8_t>(ctx.intact[k] == 0);
        workspace.row_failed[i] = failed;
      }
    }
    const bool penalty = ctx.pen2 != 0 || ctx.pen3 != 0;
    auto all_points = [&]<bool kEnergy, bool kPenalty>() {
      if (ctx.stencil != nullptr) {
#pragma omp for schedule(static, kChunk)
        for (std::size_t i = 0; i < n; ++i) process_point<kEnergy, kPenalty, true>(ctx, i, th);
      } else {
#pragma omp for schedule(static, kChunk)
        for (std::size_t i = 0; i < n; ++i) process_point<kEnergy, kPenalty, false>(ctx, i, th);
      }
    };
    if (with_energy && penalty) {
      all_points.template operator()<true, true>();
    } else if (with_energy) {
      all_points.template operator()<true, false>();
    } else if (penalty) {
      all_points.template operator()<false, true>();
    } else {
      all_points.template operator()<false, false>();
    }
    // Fixed-order reduction: thread 0, 1, ... for every point.
#pragma omp for schedule(static)
    for (std::size_t p = 0; p < n; ++p) {
      Vec3 f = workspace.thread(0).force[p];
      for (int s = 1; s < team; ++s) f += workspace.thread(static_cast<std::size_t>(s)).force[p];
      body.force_density[p] = f;
      if (with_energy) {
        double e = workspace.thread(0).energy[p];
        for (int s = 1; s < team; ++s) e += workspace.thread(static_cast<std::size_t>(s)).energy[p];
        body.strain_energy_density[p] = e;
      }
    }
  }
  SymmetricKernelStats stats;
  for (int s = 0; s < team; ++s) {
    const SymmetricKernelStats& x = workspace.thread(static_cast<std::size_t>(s)).stats;
    stats.bonds += x.bonds;
    stats.triangles += x.triangles;
    stats.tetrahedra += x.tetrahedra;
    stats.triangles_per_vertex += x.triangles_per_vertex;
    stats.tetrahedra_per_vertex += x.tetrahedra_per_vertex;
    stats.inverted_triangles += x.inverted_triangles;
    stats.inverted_tetrahedra += x.inverted_tetrahedra;
  }
  return stats;
}

SymmetricKernelStats compute_internal_force_symmetric(Body& body, bool with_energy) {
  // One workspace per calling thread: two host threads may evaluate two bodies at once.
  thread_local SymmetricKernelWorkspace workspace;
  return compute_internal_force_symmetric(body, with_energy, workspace);
}

void count_interactions_symmetric(const Body& body, std::vector<std::uint32_t>& n2,
                                  std::vector<std::uint32_t>& n3) {
  const std::size_t n = body.size();
  n2.assign(n, 0);
  n3.assign(n, 0);
  Context ctx = make_context(body);
  ctx.intact = nullptr;  // counts include failed bonds, like body.n2 / body.n3
  if (!(ctx.pairs || ctx.triples)) return;
  double min_length2 = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = body.family.offset[i]; k < body.family.offset[i + 1]; ++k)
      min_length2 = std::min(min_length2, squared_length(body, i, k));
  set_screens(ctx, std::sqrt(min_length2));
  SymmetricKernelThread t;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t m = load_upper_family(ctx, i, t, true);
    const std::size_t W = t.words;
    const auto ii = static_cast<std::uint32_t>(i);
    for (std::size_t a = 0; a + 1 < m; ++a) {
      const std::uint64_t* ra = &t.adj[a * W];
      for (std::size_t b = a + 1; b < m; ++b) {
        if (!bit(ra, b)) continue;
        const std::uint32_t vj = t.up[a], vk = t.up[b];
        const Vec3 P(t.Rx[a], t.Ry[a], t.Rz[a]), Q(t.Rx[b], t.Ry[b], t.Rz[b]);
        const Vec3 PQ = P.cross(Q);
        if (ctx.pairs) {
          const unsigned mask = triangle_mask(ctx, PQ.norm(), ii, vj, vk);
          n2[i] += 2 * (mask & 1);
          n2[vj] += 2 * ((mask >> 1) & 1);
          n2[vk] += 2 * ((mask >> 2) & 1);
        }
        if (!ctx.triples) continue;
        const std::uint64_t* rb = &t.adj[b * W];
        for (std::size_t c = b + 1; c < m; ++c) {
          if (!bit(ra, c) || !bit(rb, c)) continue;
          const Vec3 R(t.Rx[c], t.Ry[c], t.Rz[c]);
          const unsigned mask = tetrahedron_mask(ctx, std::abs(PQ.dot(R)), ii, vj, vk, t.up[c]);
          n3[i] += 6 * (mask & 1);
          n3[vj] += 6 * ((mask >> 1) & 1);
          n3[vk] += 6 * ((mask >> 2) & 1);
          n3[t.up[c]] += 6 * ((mask >> 3) & 1);
        }
      }
    }
  }
}

}  // namespace ckpd
