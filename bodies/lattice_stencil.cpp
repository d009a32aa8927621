#include "bodies/lattice_stencil.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>

#include "bodies/body.hpp"
#include "bodies/bond_family.hpp"

namespace ckpd {

namespace {

using Offset = std::array<int, 3>;

// A point is on the lattice when it sits within this many times the round-off of its
// coordinates (relative 2.2e-16 of |X|) from a lattice site: the stencil's exact geometry then
// differs from the one its positions give by round-off only, as the reference kernel's own.
constexpr double kSiteRoundoff = 1e-13;
// A set whose |A| / (L L) or |V| / (L L L) is within this relative distance of the body's
// degenerate fraction could be decided either way by the reference's floating-point geometry.
constexpr double kThresholdMargin = 1e-6;

bool upper(const Offset& o) {
  return o[2] > 0 || (o[2] == 0 && (o[1] > 0 || (o[1] == 0 && o[0] > 0)));
}
bool lex_less(const Offset& a, const Offset& b) {
  if (a[2] != b[2]) return a[2] < b[2];
  if (a[1] != b[1]) return a[1] < b[1];
  return a[0] < b[0];
}
Offset minus(const Offset& a, const Offset& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
std::array<long long, 3> cross(const Offset& a, const Offset& b) {
  return {static_cast<long long>(a[1]) * b[2] - static_cast<long long>(a[2]) * b[1],
          static_cast<long long>(a[2]) * b[0] - static_cast<long long>(a[0]) * b[2],
          static_cast<long long>(a[0]) * b[1] - static_cast<long long>(a[1]) * b[0]};
}
double norm(const Offset& a) {
  return std::sqrt(double(a[0]) * a[0] + double(a[1]) * a[1] + double(a[2]) * a[2]);
}
double norm(const std::array<long long, 3>& a) {
  return std::sqrt(double(a[0]) * double(a[0]) + double(a[1]) * double(a[1]) +
                   double(a[2]) * double(a[2]));
}
bool within(const Offset& o, double spacing, double horizon) {
  return within_horizon(Vec3(o[0] * spacing, o[1] * spacing, o[2] * spacing), horizon);
}

// Whether every vertex of a set with nonzero integer size sees it clearly above the degenerate
// fraction f: size / (product of the edge lengths from that vertex) > f (1 + margin).
// `edges[v]` is that product for vertex v.
bool clearly_non_degenerate(double size, const double* edges, int vertices, double f) {
  for (int v = 0; v < vertices; ++v)
    if (!(size > f * (1 + kThresholdMargin) * edges[v])) return false;
  return true;
}

void set_bit(std::uint64_t* row, std::size_t s) {
  row[s >> 6] |= std::uint64_t{1} << (s & 63);
}
bool bit(const std::uint64_t* row, std::size_t s) {
  return (row[s >> 6] >> (s & 63)) & 1;
}

}  // namespace

std::size_t LatticeStencil::bytes() const {
  return coord.size() * sizeof(std::int32_t) + slot_table.size() * sizeof(std::int32_t) +
         offset.size() * sizeof(Offset) + (inv_length.size() + length.size()) * sizeof(double) +
         (adjacency.size() + sum_inside.size()) * sizeof(std::uint64_t) +
         pair_base.size() * sizeof(std::uint32_t) +
         (inv_area.size() + area_z.size()) * sizeof(double) +
         triple_row.size() * sizeof(std::uint64_t) + triple_base.size() * sizeof(std::uint32_t) +
         inv_volume.size() * sizeof(double);
}

LatticeCoordinates lattice_coordinates(const Body& body) {
  LatticeCoordinates out;
  const std::size_t n = body.size();
  const BondFamily& family = body.family;
  if (n < 2 || family.bond_entries() == 0) {
    out.reason = "no bonds";
    return out;
  }
  if (n >= (std::size_t{1} << 31)) {
    out.reason = "too many points";
    return out;
  }
  // The spacing is the shortest bond: on a lattice, the nearest neighbour distance.
  double h2 = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = family.offset[i]; k < family.offset[i + 1]; ++k)
      h2 = std::min(h2, (body.reference_position[family.neighbour[k]] - body.reference_position[i])
                            .squaredNorm());
  const double h = std::sqrt(h2);
  std::vector<std::int32_t> coord(3 * n);
  const Vec3 origin = body.reference_position[0];
  // Lattice coordinates for spacing h; false (with the reason set) if a point is off the lattice.
  auto assign_coordinates = [&](double spacing) {
    constexpr double kLargest = double(1 << 29);
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 t = (body.reference_position[i] - origin) / spacing;
      const double tolerance =
          kSiteRoundoff * (1 + (body.reference_position[i].norm() + origin.norm()) / spacing);
      for (int d = 0; d < 3; ++d) {
        const double r = std::round(t[d]);
        if (!(std::abs(t[d] - r) <= tolerance) || std::abs(r) > kLargest) {
          std::ostringstream msg;
          msg << "point " << i << " is not on the lattice of spacing " << spacing
              << " m through point 0";
          out.reason = msg.str();
          return false;
        }
        coord[3 * i + d] = static_cast<std::int32_t>(r);
      }
      if (body.dimension == 2 && coord[3 * i + 2] != 0) {
        out.reason = "2D points off one plane";
        return false;
      }
    }
    return true;
  };
  // The shortest bond carries the rounding of two nearby positions (relative eps |X| / h); the
  // spacing that the whole body spans, from point 0 to the point farthest from it in lattice
  // steps, carries that rounding divided by the number of steps. The stencil's geometry is
  // built from the latter, so that it differs from the positions' only by their own rounding.
  if (!assign_coordinates(h)) return out;
  std::size_t far = 0;
  double far_steps2 = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double s2 = double(coord[3 * i]) * coord[3 * i] +
                      double(coord[3 * i + 1]) * coord[3 * i + 1] +
                      double(coord[3 * i + 2]) * coord[3 * i + 2];
    if (s2 > far_steps2) {
      far_steps2 = s2;
      far = i;
    }
  }
  const Vec3 steps(coord[3 * far], coord[3 * far + 1], coord[3 * far + 2]);
  const double spacing = (body.reference_position[far] - origin).dot(steps) / far_steps2;
  if (!assign_coordinates(spacing)) return out;
  out.spacing = spacing;
  out.coord = std::move(coord);
  return out;
}

StencilBuild build_lattice_stencil(const Body& body) {
  StencilBuild out;
  auto fail = [&](const std::string& why) {
    out.reason = why;
    return out;
  };
  const std::size_t n = body.size();
  const BondFamily& family = body.family;
  if (n < 2 || family.bond_entries() == 0) return fail("no bonds");
  if (n >= (std::size_t{1} << 31)) return fail("too many points");

  LatticeCoordinates lattice = lattice_coordinates(body);
  if (lattice.coord.empty()) return fail(lattice.reason);
  auto stencil = std::make_shared<LatticeStencil>();
  LatticeStencil& st = *stencil;
  st.coord = std::move(lattice.coord);
  st.spacing = lattice.spacing;
  const double spacing = lattice.spacing;
  auto coord_of = [&](std::size_t i) {
    return Offset{st.coord[3 * i], st.coord[3 * i + 1], st.coord[3 * i + 2]};
  };
  for (std::size_t i = 0; i + 1 < n; ++i)
    if (!lex_less(coord_of(i), coord_of(i + 1)))
      return fail("points are not numbered in (z, y, x) lattice order");

  // The body's box in lattice coordinates.
  Offset lo = coord_of(0), hi = coord_of(0);
  for (std::size_t i = 1; i < n; ++i)
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], st.coord[3 * i + d]);
      hi[d] = std::max(hi[d], st.coord[3 * i + d]);
    }

  // All offsets within the horizon that fit in the body's box (a thin body needs only the
  // offsets across its thickness: a two-layer disc at m = 8 has |dz| <= 1, which keeps its
  // triple table small), and the upper ones in (z, y, x) order.
  const int range = static_cast<int>(std::ceil(body.horizon / spacing)) + 1;
  std::array<int, 3> extent{};
  for (int d = 0; d < 3; ++d) extent[d] = std::min(range, hi[d] - lo[d]);
  std::vector<Offset> all;
  for (int z = -extent[2]; z <= extent[2]; ++z)
    for (int y = -extent[1]; y <= extent[1]; ++y)
      for (int x = -extent[0]; x <= extent[0]; ++x) {
        const Offset o{x, y, z};
        if ((x || y || z) && within(o, spacing, body.horizon)) all.push_back(o);
      }
  int reach = 0;
  for (const Offset& o : all)
    for (int d = 0; d < 3; ++d) reach = std::max(reach, std::abs(o[d]));
  st.reach = reach;
  const int side = 2 * reach + 1;
  auto table_index = [&](const Offset& o) {
    return static_cast<std::size_t>(((o[2] + reach) * side + o[1] + reach) * side + o[0] + reach);
  };
  std::vector<std::uint8_t> in_stencil(static_cast<std::size_t>(side) * side * side, 0);
  for (const Offset& o : all) in_stencil[table_index(o)] = 1;
  for (const Offset& o : all)
    if (upper(o)) st.offset.push_back(o);
  std::sort(st.offset.begin(), st.offset.end(), lex_less);
  st.slots = st.offset.size();
  st.words = (st.slots + 63) / 64;
  st.slot_table.assign(in_stencil.size(), -1);
  for (std::size_t s = 0; s < st.slots; ++s)
    st.slot_table[table_index(st.offset[s])] = static_cast<std::int32_t>(s);

  // Every family must be exactly the stencil's offsets whose site holds a point: its bonds are
  // stencil offsets, and it has as many as there are occupied stencil sites around the point.
  const double sites =
      (double(hi[0]) - lo[0] + 1) * (double(hi[1]) - lo[1] + 1) * (double(hi[2]) - lo[2] + 1);
  if (sites > 64.0 * double(n) + 1e6) return fail("points fill too little of their lattice box");
  const std::size_t ex = static_cast<std::size_t>(hi[0] - lo[0] + 1),
                    ey = static_cast<std::size_t>(hi[1] - lo[1] + 1);
  std::vector<std::uint8_t> occupied(static_cast<std::size_t>(sites), 0);
  auto site = [&](const Offset& c) {
    return (static_cast<std::size_t>(c[2] - lo[2]) * ey + static_cast<std::size_t>(c[1] - lo[1])) *
               ex +
           static_cast<std::size_t>(c[0] - lo[0]);
  };
  for (std::size_t i = 0; i < n; ++i) occupied[site(coord_of(i))] = 1;
  long long mismatch = -1;
#pragma omp parallel for schedule(static) reduction(max : mismatch)
  for (std::size_t i = 0; i < n; ++i) {
    const Offset c = coord_of(i);
    std::size_t count = 0;
    for (const Offset& o : all) {
      const Offset t{c[0] + o[0], c[1] + o[1], c[2] + o[2]};
      bool inside = true;
      for (int d = 0; d < 3; ++d) inside = inside && t[d] >= lo[d] && t[d] <= hi[d];
      if (inside && occupied[site(t)]) ++count;
    }
    bool ok = count == family.family_size(i);
    for (std::size_t k = family.offset[i]; ok && k < family.offset[i + 1]; ++k) {
      const Offset o = minus(coord_of(family.neighbour[k]), c);
      bool inside = true;
      for (int d = 0; d < 3; ++d) inside = inside && std::abs(o[d]) <= reach;
      ok = inside && in_stencil[table_index(o)];
    }
    if (!ok) mismatch = std::max(mismatch, static_cast<long long>(i));
  }
  if (mismatch >= 0) {
    std::ostringstream msg;
    msg << "the family of point " << mismatch << " is not the lattice stencil's";
    return fail(msg.str());
  }

  const std::size_t M = st.slots, W = st.words;
  st.length.resize(M);
  st.inv_length.resize(M);
  for (std::size_t s = 0; s < M; ++s) {
    // The offset vector in metres, as the family sees it: spacing o, then its length.
    const Vec3 v(st.offset[s][0] * spacing, st.offset[s][1] * spacing, st.offset[s][2] * spacing);
    st.length[s] = v.norm();
    st.inv_length[s] = 1 / st.length[s];
  }
  const bool pairs = body.has_pairs(), triples = body.has_triples();
  if (!pairs && !triples) {
    out.stencil = std::move(stencil);
    return out;
  }

  st.adjacency.assign(M * W, 0);
  st.pair_base.resize(M);
  for (std::size_t a = 0; a < M; ++a) {
    st.pair_base[a] = static_cast<std::uint32_t>(st.pairs);
    for (std::size_t b = a + 1; b < M; ++b)
      if (within(minus(st.offset[b], st.offset[a]), spacing, body.horizon)) {
        set_bit(&st.adjacency[a * W], b);
        ++st.pairs;
      }
  }
  st.sum_inside.assign(M * W, 0);
  for (std::size_t a = 0; a < M; ++a)
    for (std::size_t s = 0; s < M; ++s)
      if (st.sum_slot(a, s) >= 0) set_bit(&st.sum_inside[a * W], s);
  const double f = body.degenerate_fraction;
  if (!(f >= 1e-12)) return fail("degenerate_fraction below 1e-12");

  // Count the triples first: their table is what can grow too large.
  std::size_t triple_count = 0;
  if (triples) {
    for (std::size_t a = 0; a < M; ++a)
      for (std::size_t b = a + 1; b < M; ++b) {
        if (!bit(&st.adjacency[a * W], b)) continue;
        for (std::size_t w = 0; w < W; ++w)
          triple_count += static_cast<std::size_t>(
              std::popcount(st.adjacency[a * W + w] & st.adjacency[b * W + w]));
      }
  }
  const std::size_t estimate = st.coord.size() * 4 + st.slot_table.size() * 4 + M * (W * 8 + 40) +
                               st.pairs * (pairs ? 16 : 0) +
                               (triples ? st.pairs * (W * 8 + 4) + triple_count * 8 : 0);
  if (estimate > kStencilMemoryLimit) {
    std::ostringstream msg;
    msg << "its tables would need " << estimate / (1 << 20) << " MiB (limit "
        << kStencilMemoryLimit / (1 << 20) << " MiB)";
    return fail(msg.str());
  }

  if (pairs) {
    st.inv_area.assign(st.pairs, 0);
    st.area_z.assign(st.pairs, 0);
  }
  if (triples) {
    st.triple_row.assign(st.pairs * W, 0);
    st.triple_base.resize(st.pairs);
    st.inv_volume.reserve(triple_count);
  }
  const double h3d = spacing * spacing * spacing;
  std::size_t pair = 0;
  for (std::size_t a = 0; a < M; ++a) {
    const Offset& P = st.offset[a];
    for (std::size_t b = a + 1; b < M; ++b) {
      if (!bit(&st.adjacency[a * W], b)) continue;
      const Offset& Q = st.offset[b];
      const Offset PQ = minus(Q, P);
      const auto area = cross(P, Q);
      if (pairs && (area[0] || area[1] || area[2])) {
        // Products of the two edges from each vertex: 0 (P, Q), a (P, Q - P), b (Q, Q - P).
        const double edges[3] = {norm(P) * norm(Q), norm(P) * norm(PQ), norm(Q) * norm(PQ)};
        if (!clearly_non_degenerate(norm(area), edges, 3, f))
          return fail("a triangle's degeneracy depends on the vertex (degenerate_fraction)");
        const Vec3 Ph(P[0] * spacing, P[1] * spacing, P[2] * spacing),
            Qh(Q[0] * spacing, Q[1] * spacing, Q[2] * spacing);
        const Vec3 A = Ph.cross(Qh);
        st.inv_area[pair] = 1 / A.norm();
        st.area_z[pair] = A.z();
      }
      if (triples) {
        st.triple_base[pair] = static_cast<std::uint32_t>(st.inv_volume.size());
        std::uint64_t* row = &st.triple_row[pair * W];
        for (std::size_t c = b + 1; c < M; ++c) {
          if (!bit(&st.adjacency[a * W], c) || !bit(&st.adjacency[b * W], c)) continue;
          const Offset& R = st.offset[c];
          const long long volume =
              area[0] * R[0] + area[1] * R[1] + area[2] * R[2];  // P . (Q x R) = (P x Q) . R
          if (volume == 0) continue;
          const Offset PR = minus(R, P), QR = minus(R, Q);
          const double edges[4] = {norm(P) * norm(Q) * norm(R), norm(P) * norm(PQ) * norm(PR),
                                   norm(Q) * norm(PQ) * norm(QR), norm(R) * norm(PR) * norm(QR)};
          if (!clearly_non_degenerate(std::abs(double(volume)), edges, 4, f))
            return fail("a tetrahedron's degeneracy depends on the vertex (degenerate_fraction)");
          set_bit(row, c);
          st.inv_volume.push_back(1 / (double(volume) * h3d));
          ++st.triples;
        }
      }
      ++pair;
    }
  }
  out.stencil = std::move(stencil);
  return out;
}

}  // namespace ckpd
