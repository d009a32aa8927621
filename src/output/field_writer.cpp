#include "src/output/field_writer.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "src/engine/contact_coupling.hpp"
#include "src/engine/ranks.hpp"
#include "src/output/hdf5_io.hpp"
#include "src/output/output_share.hpp"

namespace ckpd {

namespace {

using hdf5::Handle;

std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::size_t dataset_rows(hid_t group, const std::string& name) {
  Handle set(H5Dopen2(group, name.c_str(), H5P_DEFAULT), H5Dclose, "open " + name);
  Handle space(H5Dget_space(set), H5Sclose, "read a shape");
  hsize_t dims[2] = {0, 0};
  H5Sget_simple_extent_dims(space, dims, nullptr);
  return static_cast<std::size_t>(dims[0]);
}

// The fields a mesh wall's surface carries (its vertices move rigidly; the rest are point
// fields of deformable bodies).
bool wall_field(const std::string& name) {
  return name == "position" || name == "reference_position" || name == "displacement" ||
         name == "body_id" || name == "point_id";
}

// A mesh wall's surface at the wall's current pose: x = centre + R (X - c0). Every rank of a
// shared file makes the same calls; rank 0 writes the rows (alike_rows).
void write_wall_group(hid_t group, const Simulation& sim, const SceneBody& sb, std::size_t b,
                      const std::vector<std::string>& fields) {
  const TriangleMesh& surface = *sb.wall_surface;
  const MeshWall::Pose pose = sb.wall->pose(point_set(sb));
  const Vec3& c0 = sb.wall->carriers().centre;
  const std::size_t n = surface.vertex.size();
  const auto share = [&sim](std::size_t rows) { return alike_rows(sim, rows); };
  std::vector<Vec3> x(n);
  for (std::size_t v = 0; v < n; ++v) x[v] = pose.centre + pose.rotation * (surface.vertex[v] - c0);
  std::vector<std::int32_t> cells;
  cells.reserve(3 * surface.triangle.size());
  for (const auto& t : surface.triangle)
    for (std::uint32_t v : t) cells.push_back(static_cast<std::int32_t>(v));
  hdf5::write_int32(group, "triangles", cells, share(surface.triangle.size()), 3);
  for (const std::string& f : fields) {
    if (f == "position") {
      hdf5::write_vectors(group, f, x, share(n));
    } else if (f == "reference_position") {
      hdf5::write_vectors(group, f, surface.vertex, share(n));
    } else if (f == "displacement") {
      std::vector<Vec3> u(n);
      for (std::size_t v = 0; v < n; ++v) u[v] = x[v] - surface.vertex[v];
      hdf5::write_vectors(group, f, u, share(n));
    } else if (f == "body_id") {
      hdf5::write_int32(group, f, std::vector<std::int32_t>(n, static_cast<std::int32_t>(b)),
                        share(n), 1);
    } else if (f == "point_id") {
      std::vector<std::int32_t> id(n);
      for (std::size_t v = 0; v < n; ++v) id[v] = static_cast<std::int32_t>(v);
      hdf5::write_int32(group, f, id, share(n), 1);
    }
  }
}

// A point body's fields: every row of the whole body, or in a shared file this rank's rows
// (output_share.hpp), each field taken from the body the rows are in.
void write_point_group(hid_t group, const Simulation& sim, std::size_t b,
                       const std::vector<std::string>& fields, std::vector<double>& buffer) {
  const BodyShare share = body_share(sim, b);
  // The Polyvertex connectivity: point k is cell k.
  std::vector<std::int32_t> ids(share.local.size());
  for (std::size_t k = 0; k < ids.size(); ++k)
    ids[k] = static_cast<std::int32_t>(share.whole_index(k));
  hdf5::write_int32(group, "connectivity", ids, share.points, 1);
  const FieldSource source{*share.body, b, share.whole_of_local,
                           share.whole_of_local ? &sim.whole_scene().bodies[b].body : nullptr};
  std::vector<double> scratch;
  for (const std::string& f : fields) {
    const FieldSpec& spec = *find_field(f);
    spec.extract(source, buffer);
    const auto columns = static_cast<std::size_t>(spec.components);
    const std::vector<double>& rows = rows_of(share, buffer, columns, scratch);
    if (spec.number == FieldNumber::int32) {
      const std::vector<std::int32_t> values(rows.begin(), rows.end());
      hdf5::write_int32(group, f, values, share.points, columns);
    } else {
      hdf5::write_doubles(group, f, rows.data(), share.points, columns);
    }
  }
}

}  // namespace

FieldWriter::FieldWriter(ListOnly, std::string directory, const std::vector<std::string>& fields)
    : directory_(std::move(directory)) {
  fields_.push_back("position");
  for (const std::string& f : fields) {
    if (!find_field(f))
      throw std::invalid_argument("unknown output field '" + f + "' (known: " + known_field_list() +
                                  ")");
    if (std::find(fields_.begin(), fields_.end(), f) == fields_.end()) fields_.push_back(f);
  }
}

FieldWriter FieldWriter::follower(std::string directory, const std::vector<std::string>& fields,
                                  std::size_t kept) {
  FieldWriter writer(ListOnly{}, std::move(directory), fields);
  writer.frames_.resize(kept);  // only their number is used: the next frame's name
  return writer;
}

FieldWriter::FieldWriter(std::string directory, const std::vector<std::string>& fields,
                         long long resume_after_step)
    : FieldWriter(ListOnly{}, std::move(directory), fields) {
  std::error_code ec;
  std::filesystem::create_directories(directory_ + "/fields", ec);
  if (ec) throw std::runtime_error(directory_ + "/fields: cannot create: " + ec.message());
  hdf5::silence_errors();
  std::vector<std::filesystem::path> existing;
  for (const auto& entry : std::filesystem::directory_iterator(directory_ + "/fields"))
    if (entry.path().extension() == ".h5") existing.push_back(entry.path());
  std::sort(existing.begin(), existing.end());
  for (const auto& path : existing) {
    // A restart keeps the frames of the interrupted run up to its checkpoint, in order; frames
    // of any other run in this folder must not be mixed with this run's.
    bool keep = false;
    if (resume_after_step >= 0 && path.filename() == frame_name(frames_.size())) {
      try {
        hdf5::Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose,
                          "open " + path.string());
        const long long step = hdf5::read_int64_attribute(file, "step");
        if (step <= resume_after_step) {
          Frame frame{"fields/" + path.filename().string(),
                      hdf5::read_double_attribute(file, "time"),
                      {},
                      {}};
          for (long long b = 0;; ++b) {
            const std::string group = "body_" + std::to_string(b);
            if (H5Lexists(file, group.c_str(), H5P_DEFAULT) <= 0) break;
            hdf5::Handle g(H5Gopen2(file, group.c_str(), H5P_DEFAULT), H5Gclose, "open " + group);
            frame.points.push_back(dataset_rows(g, "position"));
            frame.triangles.push_back(
                H5Lexists(g, "triangles", H5P_DEFAULT) > 0 ? dataset_rows(g, "triangles") : 0);
          }
          frames_.push_back(std::move(frame));
          keep = true;
        }
      } catch (const std::runtime_error&) {
        keep = false;  // unreadable: written after the checkpoint, or damaged; rewritten below
      }
    }
    if (!keep) std::filesystem::remove(path, ec);
  }
  std::filesystem::remove(directory_ + "/fields.xdmf", ec);
}

std::string FieldWriter::frame_name(std::size_t index) {
  std::ostringstream name;
  name << "frame_" << std::setw(6) << std::setfill('0') << index << ".h5";
  return name.str();
}

bool FieldWriter::needs_energy() const {
  return std::any_of(fields_.begin(), fields_.end(),
                     [](const std::string& f) { return find_field(f)->needs_energy; });
}

void FieldWriter::write_frame(const Simulation& sim) {
  const std::string name = "fields/" + frame_name(frames_.size());
  const std::string final_path = directory_ + "/" + name;
  const std::string temp_path = final_path + ".partial";
  Frame frame{name, sim.time(), {}, {}};
  // A shared file: every rank writes its points into it; rank 0 renames it and writes the XDMF.
  const bool shared = shared_output(sim);
  const bool root = !shared || ranks::root();
  {
    Handle file(shared ? hdf5::create_shared_file(temp_path)
                       : H5Fcreate(temp_path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
                H5Fclose, "create " + temp_path);
    hdf5::write_double_attribute(file, "time", sim.time());
    hdf5::write_int64_attribute(file, "step", sim.step());
    const auto& bodies = output_scene(sim).bodies;
    std::vector<double> buffer;
    for (std::size_t b = 0; b < bodies.size(); ++b) {
      const SceneBody& sb = bodies[b];
      Handle group(H5Gcreate2(file, ("body_" + std::to_string(b)).c_str(), H5P_DEFAULT, H5P_DEFAULT,
                              H5P_DEFAULT),
                   H5Gclose, "create a body group");
      hdf5::write_string_attribute(group, "name", sb.body.name);
      hdf5::write_int64_attribute(group, "dimension", sb.body.dimension);
      if (sb.wall && sb.wall_surface) {
        write_wall_group(group, sim, sb, b, fields_);
        frame.points.push_back(sb.wall_surface->vertex.size());
        frame.triangles.push_back(sb.wall_surface->triangle.size());
      } else {
        write_point_group(group, sim, b, fields_, buffer);
        frame.points.push_back(sim.whole_scene().bodies[b].body.size());
        frame.triangles.push_back(0);
      }
    }
    if (H5Fflush(file, H5F_SCOPE_GLOBAL) < 0)
      throw std::runtime_error("HDF5: cannot flush " + temp_path);
  }
  if (root) {
    std::error_code ec;
    std::filesystem::rename(temp_path, final_path, ec);
    if (ec) throw std::runtime_error(final_path + ": cannot write: " + ec.message());
  }
  frames_.push_back(std::move(frame));
  if (root) write_xdmf(sim);
}

void FieldWriter::write_xdmf(const Simulation& sim) const {
  const std::string path = directory_ + "/fields.xdmf";
  const std::string temp = path + ".partial";
  {
    std::ofstream x(temp);
    x << std::setprecision(17);
    x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n <Domain>\n"
      << "  <Grid Name=\"run\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    const auto& bodies = sim.whole_scene().bodies;
    for (const Frame& frame : frames_) {
      x << "   <Grid Name=\"" << frame.file << "\" GridType=\"Collection\" "
        << "CollectionType=\"Spatial\">\n    <Time Value=\"" << frame.time << "\"/>\n";
      for (std::size_t b = 0; b < bodies.size(); ++b) {
        const std::size_t n = frame.points[b];
        const std::size_t triangles = frame.triangles[b];
        const std::string h5 = frame.file + ":/body_" + std::to_string(b) + "/";
        auto item = [&](const std::string& dataset, std::size_t rows, int columns,
                        FieldNumber number) {
          const bool integer = number == FieldNumber::int32;
          x << "      <DataItem Dimensions=\"" << rows;
          if (columns > 1) x << " " << columns;
          x << "\" NumberType=\"" << (integer ? "Int" : "Float") << "\" Precision=\""
            << (integer ? 4 : 8) << "\" Format=\"HDF\">" << h5 << dataset << "</DataItem>\n";
        };
        x << "    <Grid Name=\"" << xml_escape(bodies[b].body.name) << "\" GridType=\"Uniform\">\n";
        if (triangles > 0) {
          x << "     <Topology TopologyType=\"Triangle\" NumberOfElements=\"" << triangles
            << "\" NodesPerElement=\"3\">\n";
          item("triangles", triangles, 3, FieldNumber::int32);
        } else {
          x << "     <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n
            << "\" NodesPerElement=\"1\">\n";
          item("connectivity", n, 1, FieldNumber::int32);
        }
        x << "     </Topology>\n     <Geometry GeometryType=\"XYZ\">\n";
        item("position", n, 3, FieldNumber::float64);
        x << "     </Geometry>\n";
        for (const std::string& f : fields_) {
          if (f == "position" || (triangles > 0 && !wall_field(f))) continue;
          const FieldSpec& spec = *find_field(f);
          x << "     <Attribute Name=\"" << f << "\" AttributeType=\""
            << xdmf_attribute_type(spec.components) << "\" Center=\"Node\">\n";
          item(f, n, spec.components, spec.number);
          x << "     </Attribute>\n";
        }
        x << "    </Grid>\n";
      }
      x << "   </Grid>\n";
    }
    x << "  </Grid>\n </Domain>\n</Xdmf>\n";
    if (!x) throw std::runtime_error(temp + ": cannot write");
  }
  std::error_code ec;
  std::filesystem::rename(temp, path, ec);
  if (ec) throw std::runtime_error(path + ": cannot write: " + ec.message());
}

}  // namespace ckpd
