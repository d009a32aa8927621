#pragma once
// Closed triangle surfaces made in the tests (sphere, cube, torus, notched plate), and writers
// for ASCII STL, binary STL, OBJ and PLY. Coordinates are rounded to float first, so every
// format carries the same numbers (binary STL and assimp hold floats).
#include <cmath>
#include <cstdint>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "src/geometry/mesh/triangle_mesh.hpp"

namespace ckpd::testing {

inline void round_to_float(TriangleMesh& m) {
  for (Vec3& v : m.vertex)
    for (int d = 0; d < 3; ++d) v[d] = static_cast<double>(static_cast<float>(v[d]));
}

// UV sphere: `rings` latitude bands, `segments` longitudes, poles as single vertices.
inline TriangleMesh sphere_mesh(double radius, int rings, int segments,
                                Vec3 centre = Vec3::Zero()) {
  TriangleMesh m;
  const double pi = std::numbers::pi;
  m.vertex.push_back(centre + Vec3(0, 0, -radius));
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double th = pi * r / rings - pi / 2, ph = 2 * pi * s / segments;
      m.vertex.push_back(centre + radius * Vec3(std::cos(th) * std::cos(ph),
                                                std::cos(th) * std::sin(ph), std::sin(th)));
    }
  m.vertex.push_back(centre + Vec3(0, 0, radius));
  auto at = [&](int r, int s) {
    return static_cast<std::uint32_t>(1 + (r - 1) * segments + (s % segments));
  };
  const auto top = static_cast<std::uint32_t>(m.vertex.size() - 1);
  for (int s = 0; s < segments; ++s) {
    m.triangle.push_back({0, at(1, s + 1), at(1, s)});
    m.triangle.push_back({top, at(rings - 1, s), at(rings - 1, s + 1)});
  }
  for (int r = 1; r < rings - 1; ++r)
    for (int s = 0; s < segments; ++s) {
      m.triangle.push_back({at(r, s), at(r, s + 1), at(r + 1, s + 1)});
      m.triangle.push_back({at(r, s), at(r + 1, s + 1), at(r + 1, s)});
    }
  round_to_float(m);
  return m;
}

// Torus about z: major radius R, tube radius r.
inline TriangleMesh torus_mesh(double R, double r, int around, int tube) {
  TriangleMesh m;
  const double pi = std::numbers::pi;
  for (int i = 0; i < around; ++i)
    for (int j = 0; j < tube; ++j) {
      const double u = 2 * pi * i / around, v = 2 * pi * j / tube;
      m.vertex.emplace_back((R + r * std::cos(v)) * std::cos(u),
                            (R + r * std::cos(v)) * std::sin(u), r * std::sin(v));
    }
  auto at = [&](int i, int j) {
    return static_cast<std::uint32_t>((i % around) * tube + (j % tube));
  };
  for (int i = 0; i < around; ++i)
    for (int j = 0; j < tube; ++j) {
      m.triangle.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangle.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  round_to_float(m);
  return m;
}

// A simple polygon (counter-clockwise in xy) extruded from z = 0 to z = thickness; `caps` are
// the cap triangles as polygon-vertex indices (counter-clockwise).
inline TriangleMesh extrude(const std::vector<std::pair<double, double>>& polygon,
                            const std::vector<std::array<std::uint32_t, 3>>& caps,
                            double thickness) {
  TriangleMesh m;
  const auto n = static_cast<std::uint32_t>(polygon.size());
  for (double z : {0.0, thickness})
    for (const auto& [x, y] : polygon) m.vertex.emplace_back(x, y, z);
  for (const auto& c : caps) {
    m.triangle.push_back({c[0], c[2], c[1]});              // bottom, facing -z
    m.triangle.push_back({c[0] + n, c[1] + n, c[2] + n});  // top, facing +z
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t j = (i + 1) % n;
    m.triangle.push_back({i, j, j + n});
    m.triangle.push_back({i, j + n, i + n});
  }
  round_to_float(m);
  return m;
}

inline TriangleMesh cube_mesh(double side) {
  return extrude({{0, 0}, {side, 0}, {side, side}, {0, side}}, {{0, 1, 2}, {0, 2, 3}}, side);
}

// A W x H plate, `thickness` thick, with a notch (b - a) wide and d deep cut into its top edge.
// Volume (W H - (b - a) d) thickness.
inline TriangleMesh notched_plate_mesh(double W, double H, double a, double b, double d,
                                       double thickness) {
  // 0 (0,0) 1 (a,0) 2 (b,0) 3 (W,0) 4 (W,H) 5 (b,H) 6 (b,H-d) 7 (a,H-d) 8 (a,H) 9 (0,H)
  return extrude(
      {{0, 0}, {a, 0}, {b, 0}, {W, 0}, {W, H}, {b, H}, {b, H - d}, {a, H - d}, {a, H}, {0, H}},
      {{0, 1, 7},
       {0, 7, 8},
       {0, 8, 9},  // left strip
       {1, 2, 6},
       {1, 6, 7},  // under the notch
       {3, 4, 5},
       {3, 5, 6},
       {3, 6, 2}},  // right strip
      thickness);
}

inline void write_ascii_stl(const TriangleMesh& m, const std::string& path) {
  std::ofstream out(path);
  out.precision(9);
  out << "solid test\n";
  for (std::size_t t = 0; t < m.triangle.size(); ++t) {
    const Vec3 n = m.area_normal(t).normalized();
    out << " facet normal " << n.x() << " " << n.y() << " " << n.z() << "\n  outer loop\n";
    for (int k = 0; k < 3; ++k) {
      const Vec3& v = m.corner(t, k);
      out << "   vertex " << v.x() << " " << v.y() << " " << v.z() << "\n";
    }
    out << "  endloop\n endfacet\n";
  }
  out << "endsolid test\n";
}

inline void write_binary_stl(const TriangleMesh& m, const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  char header[80] = "binary test mesh";
  out.write(header, 80);
  const auto count = static_cast<std::uint32_t>(m.triangle.size());
  out.write(reinterpret_cast<const char*>(&count), 4);
  for (std::size_t t = 0; t < m.triangle.size(); ++t) {
    const Vec3 n = m.area_normal(t).normalized();
    float f[12];
    for (int d = 0; d < 3; ++d) f[d] = static_cast<float>(n[d]);
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) f[3 + 3 * k + d] = static_cast<float>(m.corner(t, k)[d]);
    out.write(reinterpret_cast<const char*>(f), sizeof f);
    const std::uint16_t attribute = 0;
    out.write(reinterpret_cast<const char*>(&attribute), 2);
  }
}

inline void write_obj(const TriangleMesh& m, const std::string& path) {
  std::ofstream out(path);
  out.precision(9);
  for (const Vec3& v : m.vertex) out << "v " << v.x() << " " << v.y() << " " << v.z() << "\n";
  for (const auto& t : m.triangle)
    out << "f " << t[0] + 1 << " " << t[1] + 1 << " " << t[2] + 1 << "\n";
}

inline void write_ply(const TriangleMesh& m, const std::string& path) {
  std::ofstream out(path);
  out.precision(9);
  out << "ply\nformat ascii 1.0\nelement vertex " << m.vertex.size()
      << "\nproperty float x\nproperty float y\nproperty float z\nelement face "
      << m.triangle.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const Vec3& v : m.vertex) out << v.x() << " " << v.y() << " " << v.z() << "\n";
  for (const auto& t : m.triangle) out << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
}

}  // namespace ckpd::testing
