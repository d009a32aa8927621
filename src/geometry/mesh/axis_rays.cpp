#include "src/geometry/mesh/axis_rays.hpp"

#include <algorithm>
#include <cmath>

namespace ckpd {

AxisRays::AxisRays(const TriangleMesh& mesh, int axis)
    : mesh_(mesh), axis_(axis), iu_((axis + 1) % 3), iv_((axis + 2) % 3) {
  Vec3 lo, hi;
  mesh.bounds(lo, hi);
  u0_ = lo[iu_];
  v0_ = lo[iv_];
  const double su = hi[iu_] - lo[iu_], sv = hi[iv_] - lo[iv_];
  // About one cell per triangle, square cells.
  const double n = std::max<double>(1, static_cast<double>(mesh.triangle.size()));
  const double h = std::sqrt(std::max(su * sv, 1e-300) / n);
  nu_ = std::clamp(static_cast<int>(su / std::max(h, 1e-300)) + 1, 1, 4096);
  nv_ = std::clamp(static_cast<int>(sv / std::max(h, 1e-300)) + 1, 1, 4096);
  hu_ = su > 0 ? su / nu_ : 1;
  hv_ = sv > 0 ? sv / nv_ : 1;
  // Two passes: count per cell, then fill (triangles in index order within each cell).
  offset_.assign(static_cast<std::size_t>(nu_) * nv_ + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<std::uint32_t> fill;
    if (pass == 1) {
      for (std::size_t c = 1; c < offset_.size(); ++c) offset_[c] += offset_[c - 1];
      triangle_.resize(offset_.back());
      fill.assign(offset_.begin(), offset_.end() - 1);
    }
    for (std::uint32_t t = 0; t < mesh.triangle.size(); ++t) {
      double ulo = INFINITY, uhi = -INFINITY, vlo = INFINITY, vhi = -INFINITY;
      for (int k = 0; k < 3; ++k) {
        const Vec3& p = mesh.corner(t, k);
        ulo = std::min(ulo, p[iu_]);
        uhi = std::max(uhi, p[iu_]);
        vlo = std::min(vlo, p[iv_]);
        vhi = std::max(vhi, p[iv_]);
      }
      for (int a = cell_u(ulo); a <= cell_u(uhi); ++a)
        for (int b = cell_v(vlo); b <= cell_v(vhi); ++b) {
          const std::size_t c = static_cast<std::size_t>(b) * nu_ + a;
          if (pass == 0)
            ++offset_[c + 1];
          else
            triangle_[fill[c]++] = t;
        }
    }
  }
}

int AxisRays::cell_u(double u) const {
  return std::clamp(static_cast<int>(std::floor((u - u0_) / hu_)), 0, nu_ - 1);
}
int AxisRays::cell_v(double v) const {
  return std::clamp(static_cast<int>(std::floor((v - v0_) / hv_)), 0, nv_ - 1);
}

namespace {

// Sign of the edge function of edge (a, b) at p after the perturbation p + (eps, eps^2), and
// its unperturbed value. Called with a, b in vertex-index order.
struct EdgeSign {
  double value;
  int sign;
};

EdgeSign edge_sign(double au, double av, double bu, double bv, double pu, double pv) {
  const double value = (bu - au) * (pv - av) - (bv - av) * (pu - au);
  if (value > 0) return {value, 1};
  if (value < 0) return {value, -1};
  // value(p + (eps, eps^2)) = value + (bu - au) eps^2 - (bv - av) eps
  if (bv != av) return {0.0, bv > av ? -1 : 1};
  if (bu != au) return {0.0, bu > au ? 1 : -1};
  return {0.0, 0};  // a degenerate edge (both ends project to one point)
}

}  // namespace

void AxisRays::crossings(double u, double v, std::vector<AxisCrossing>& out) const {
  out.clear();
  if (u < u0_ || v < v0_ || u > u0_ + hu_ * nu_ || v > v0_ + hv_ * nv_) return;
  const std::size_t c = static_cast<std::size_t>(cell_v(v)) * nu_ + cell_u(u);
  for (std::uint32_t k = offset_[c]; k < offset_[c + 1]; ++k) {
    const std::uint32_t t = triangle_[k];
    const auto& tri = mesh_.triangle[t];
    EdgeSign e[3];  // e[k]: edge from corner k to corner k+1, in the triangle's winding
    bool skip = false;
    for (int j = 0; j < 3 && !skip; ++j) {
      std::uint32_t a = tri[j], b = tri[(j + 1) % 3];
      const bool flip = a > b;
      if (flip) std::swap(a, b);
      const Vec3& A = mesh_.vertex[a];
      const Vec3& B = mesh_.vertex[b];
      e[j] = edge_sign(A[iu_], A[iv_], B[iu_], B[iv_], u, v);
      if (flip) {
        e[j].value = -e[j].value;
        e[j].sign = -e[j].sign;
      }
      skip = e[j].sign == 0 || (j > 0 && e[j].sign != e[0].sign);
    }
    if (skip) continue;
    // Barycentric weights: the edge function of the edge opposite each corner.
    const double w0 = e[1].value, w1 = e[2].value, w2 = e[0].value, sum = w0 + w1 + w2;
    if (sum == 0) continue;  // only the perturbation puts the line inside: a sliver
    const double at = (w0 * mesh_.corner(t, 0)[axis_] + w1 * mesh_.corner(t, 1)[axis_] +
                       w2 * mesh_.corner(t, 2)[axis_]) /
                      sum;
    out.push_back({at, e[0].sign});
  }
  std::sort(out.begin(), out.end());
}

}  // namespace ckpd
