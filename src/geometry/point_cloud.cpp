#include "src/geometry/point_cloud.hpp"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include "src/input/case_node.hpp"

namespace ckpd {

namespace {

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  const auto last = s.find_last_not_of(" \t\r");
  return s.substr(first, last - first + 1);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) cells.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') cells.emplace_back();  // a trailing empty column
  return cells;
}

std::string join(const std::vector<std::string>& cells) {
  std::string s;
  for (const auto& c : cells) s += (s.empty() ? "" : ",") + c;
  return s;
}

}  // namespace

PointCloud read_point_cloud_csv(const std::string& path, int dimension, std::size_t max_points) {
  std::ifstream in(path);
  if (!in) throw CaseError(path + ": point-cloud file not found or not readable");
  auto fail = [&](std::size_t line, const std::string& expected, const std::string& got) {
    throw CaseError(path + ":" + std::to_string(line) + ": expected " + expected + ", got " + got);
  };

  PointCloud cloud;
  std::vector<std::string> columns;
  std::string text;
  std::size_t line = 0;
  while (std::getline(in, text)) {
    ++line;
    const std::string t = trim(text);
    if (t.empty() || t[0] == '#') continue;
    const std::vector<std::string> cells = split(t);
    if (columns.empty()) {
      // The header fixes the layout; a 3D body needs z, a 2D body may carry z = 0.
      const std::vector<std::string> xyv{"x", "y", "volume"}, xyzv{"x", "y", "z", "volume"};
      if (cells == xyzv || (cells == xyv && dimension == 2)) {
        columns = cells;
        continue;
      }
      fail(line,
           dimension == 2 ? "a header line 'x,y,volume' or 'x,y,z,volume'"
                          : "a header line 'x,y,z,volume' (a 3D body needs z)",
           "'" + t + "'");
    }
    if (cells.size() != columns.size())
      fail(line, std::to_string(columns.size()) + " comma-separated values (" + join(columns) + ")",
           std::to_string(cells.size()) + ": '" + t + "'");
    double value[4] = {0, 0, 0, 0};
    for (std::size_t c = 0; c < cells.size(); ++c) {
      const std::string& s = cells[c];
      const char* end = s.data() + s.size();
      const auto [ptr, ec] = std::from_chars(s.data(), end, value[c]);
      if (s.empty() || ec != std::errc() || ptr != end || !std::isfinite(value[c]))
        fail(line, "a finite number in column '" + columns[c] + "'", "'" + s + "'");
    }
    const bool has_z = columns.size() == 4;
    const double volume = value[columns.size() - 1];
    const double z = has_z ? value[2] : 0.0;
    if (!(volume > 0)) fail(line, "a positive volume", cells.back());
    if (dimension == 2 && z != 0) fail(line, "z = 0 for a point of a 2D body", cells[2]);
    if (cloud.position.size() == max_points)
      fail(line, "at most " + std::to_string(max_points) + " points (the body's max_points)",
           "more");
    cloud.position.emplace_back(value[0], value[1], z);
    cloud.volume.push_back(volume);
    cloud.line.push_back(line);
  }
  if (in.bad()) throw CaseError(path + ": reading the point-cloud file failed");
  if (columns.empty())
    throw CaseError(path +
                    ": expected a header line ('x,y,volume' or 'x,y,z,volume') and points, "
                    "got an empty file");
  if (cloud.position.empty())
    throw CaseError(path + ":" + std::to_string(line) +
                    ": expected points after the header, got "
                    "none");
  return cloud;
}

void check_distinct_points(const PointCloud& cloud, const std::string& path, double tolerance) {
  // Hash grid of cell size `tolerance`: coincident points share a cell or are in neighbours.
  struct Key {
    long long x, y, z;
    bool operator==(const Key&) const = default;
  };
  struct Hash {
    std::size_t operator()(const Key& k) const {
      return static_cast<std::size_t>(k.x * 73856093LL ^ k.y * 19349663LL ^ k.z * 83492791LL);
    }
  };
  std::unordered_map<Key, std::vector<std::size_t>, Hash> grid;
  auto key = [&](const Vec3& p) {
    return Key{static_cast<long long>(std::floor(p.x() / tolerance)),
               static_cast<long long>(std::floor(p.y() / tolerance)),
               static_cast<long long>(std::floor(p.z() / tolerance))};
  };
  for (std::size_t i = 0; i < cloud.position.size(); ++i) {
    const Key k = key(cloud.position[i]);
    for (long long dx = -1; dx <= 1; ++dx)
      for (long long dy = -1; dy <= 1; ++dy)
        for (long long dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find(Key{k.x + dx, k.y + dy, k.z + dz});
          if (it == grid.end()) continue;
          for (std::size_t j : it->second)
            if ((cloud.position[i] - cloud.position[j]).norm() < tolerance) {
              std::ostringstream msg;
              msg << path << ":" << cloud.line[i] << ": expected distinct points, got one within "
                  << tolerance << " m of the point on line " << cloud.line[j];
              throw CaseError(msg.str());
            }
        }
    grid[k].push_back(i);
  }
}

LatticeSample load_point_cloud(const CaseNode& node, int dimension, double spacing, double horizon,
                               std::size_t max_points) {
  const CaseNode file_node = node.required("file");
  if (auto f = node.optional("format"))
    if (f->as_string() != "csv") f->fail("a point-cloud format: csv (the only one so far)");
  node.finish();
  std::filesystem::path path = file_node.as_string();
  if (path.is_relative()) path = std::filesystem::path(node.file()).parent_path() / path;
  if (!std::filesystem::is_regular_file(path))
    file_node.fail("a point-cloud file (" + path.string() + " is not a readable file)");
  const PointCloud cloud = read_point_cloud_csv(path.string(), dimension, max_points);
  // Far below any sensible spacing, far above round-off in coordinates of order 1 m.
  check_distinct_points(cloud, path.string(), 1e-6 * spacing);
  LatticeSample sample;
  sample.position = cloud.position;
  sample.volume = cloud.volume;
  sample.full_family_volume =
      static_cast<double>(lattice_family_size(dimension, spacing, horizon)) *
      std::pow(spacing, dimension);
  return sample;
}

}  // namespace ckpd
