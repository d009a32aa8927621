#pragma once
// A body given as points rather than a shape: positions and volumes read from a CSV file, for
// geometries that no primitive covers (the curved bar of THEORY.md section 8).
//
// Format: text, one point per line, comma-separated. Lines that are blank or start with '#' are
// skipped. The first other line is the header and names the columns: `x,y,volume` (2D bodies
// only) or `x,y,z,volume` (3D; a 2D body may use it too, with z = 0 on every line). Volumes are
// in m^3 (3D) or m^2 (2D: per unit thickness) and must be positive.
#include <string>
#include <vector>

#include "bodies/vec.hpp"
#include "src/geometry/lattice.hpp"
#include "src/input/case_node.hpp"

namespace ckpd {

struct PointCloud {
  std::vector<Vec3> position;
  std::vector<double> volume;
  std::vector<std::size_t> line;  // the file line of each point (1-based), for error messages
};

// Throws CaseError "PATH:LINE: expected ..., got ..." for a missing or unreadable file, a bad
// header, a line with the wrong number of columns, a value that is not a finite number, a
// non-positive volume, a 2D point with z != 0, no points at all, or more than `max_points`.
PointCloud read_point_cloud_csv(const std::string& path, int dimension, std::size_t max_points);

// Throws CaseError naming both lines when two points lie closer than `tolerance` (coincident
// points make zero-length bonds).
void check_distinct_points(const PointCloud& cloud, const std::string& path, double tolerance);

// Reads a body's `points: {file: PATH, format: csv}` (PATH relative to the folder of the case
// file; csv is the only format so far and the default) into positions and volumes. The full
// family volume that beta is measured against is the lattice one of the nominal spacing: the
// number of square/cubic lattice offsets of spacing `spacing` within `horizon`, times
// spacing^dimension, exactly what a lattice-sampled body of that spacing uses.
LatticeSample load_point_cloud(const CaseNode& node, int dimension, double spacing, double horizon,
                               std::size_t max_points);

}  // namespace ckpd
