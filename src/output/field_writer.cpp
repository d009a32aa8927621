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
#include "src/output/content_hash.hpp"
#include "src/output/durable_file.hpp"
#include "src/output/hdf5_io.hpp"
#include "src/output/output_paths.hpp"
#include "src/output/output_share.hpp"

namespace ckpd {

namespace {

using hdf5::Handle;

std::size_t dataset_rows(hid_t group, const std::string& name) {
  Handle set(H5Dopen2(group, name.c_str(), H5P_DEFAULT), H5Dclose, "open " + name);
  Handle space(H5Dget_space(set), H5Sclose, "read a shape");
  hsize_t dims[2] = {0, 0};
  H5Sget_simple_extent_dims(space, dims, nullptr);
  return static_cast<std::size_t>(dims[0]);
}

// A mesh wall's surface at the wall's current pose: x = centre + R (X - c0). Every rank of a
// shared file makes the same calls; rank 0 writes the rows (alike_rows).
void write_wall_group(hid_t group, const Simulation& sim, const SceneBody& sb, std::size_t b,
                      const std::vector<std::string>& fields, hdf5::RowsHash& hash) {
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
  hdf5::write_int32(group, "triangles", cells, share(surface.triangle.size()), 3, &hash);
  for (const std::string& f : fields) {
    if (f == "position") {
      hdf5::write_vectors(group, f, x, share(n), &hash);
    } else if (f == "reference_position") {
      hdf5::write_vectors(group, f, surface.vertex, share(n), &hash);
    } else if (f == "displacement") {
      std::vector<Vec3> u(n);
      for (std::size_t v = 0; v < n; ++v) u[v] = x[v] - surface.vertex[v];
      hdf5::write_vectors(group, f, u, share(n), &hash);
    } else if (f == "body_id") {
      hdf5::write_int32(group, f, std::vector<std::int32_t>(n, static_cast<std::int32_t>(b)),
                        share(n), 1, &hash);
    } else if (f == "point_id") {
      std::vector<std::int32_t> id(n);
      for (std::size_t v = 0; v < n; ++v) id[v] = static_cast<std::int32_t>(v);
      hdf5::write_int32(group, f, id, share(n), 1, &hash);
    }
  }
}

// A point body's fields: every row of the whole body, or in a shared file this rank's rows
// (output_share.hpp), each field taken from the body the rows are in.
void write_point_group(hid_t group, const Simulation& sim, std::size_t b,
                       const std::vector<std::string>& fields, std::vector<double>& buffer,
                       hdf5::RowsHash& hash) {
  const BodyShare share = body_share(sim, b);
  // The Polyvertex connectivity: point k is cell k.
  std::vector<std::int32_t> ids(share.local.size());
  for (std::size_t k = 0; k < ids.size(); ++k)
    ids[k] = static_cast<std::int32_t>(share.whole_index(k));
  hdf5::write_int32(group, "connectivity", ids, share.points, 1, &hash);
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
      hdf5::write_int32(group, f, values, share.points, columns, &hash);
    } else {
      hdf5::write_doubles(group, f, rows.data(), share.points, columns, &hash);
    }
  }
}

// A frame's hash: its attributes (time, step, each body's name and dimension) and the sum of its
// rows' hashes (hdf5::RowsHash).
std::string frame_hash(double time, long long step, const std::vector<std::string>& names,
                       const std::vector<long long>& dimensions, std::uint64_t rows) {
  ContentHash h;
  h.value(time);
  h.value(step);
  for (std::size_t b = 0; b < names.size(); ++b) {
    h.text(names[b]);
    h.value(dimensions[b]);
  }
  h.value(rows);
  return h.hex();
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
  // A restart keeps the frames of the interrupted run up to its checkpoint, in order, as long as
  // each reads back whole; frames of any other run in this folder must not be mixed with this
  // run's.
  for (const auto& path : existing) {
    if (resume_after_step < 0 || path.filename() != frame_name(frames_.size())) break;
    try {
      long long step = 0;
      std::vector<std::string> names;
      FrameRecord frame = read_frame(directory_, frames_.size(), &step, &names);
      if (step > resume_after_step) break;
      frames_.push_back(std::move(frame));
      bodies_ = std::move(names);
    } catch (const std::runtime_error&) {
      break;  // unreadable: written after the checkpoint, or damaged; rewritten
    }
  }
  // The indexes list the kept frames before any other frame goes: at no moment do they list a
  // frame that is not there, nor lose one that is.
  if (!frames_.empty())
    write_indexes();
  else
    remove_field_indexes(directory_);
  for (std::size_t k = frames_.size(); k < existing.size(); ++k)
    std::filesystem::remove(existing[k], ec);
}

FrameRecord FieldWriter::read_frame(const std::string& directory, std::size_t index,
                                    long long* step, std::vector<std::string>* bodies) {
  const std::string name = "fields/" + frame_name(index);
  const std::string path = directory + "/" + name;
  hdf5::Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "open " + path);
  FrameRecord frame{name, hdf5::read_double_attribute(file, "time"), {}, {}};
  const long long at = hdf5::read_int64_attribute(file, "step");
  std::vector<std::string> names;
  std::vector<long long> dimensions;
  for (long long b = 0;; ++b) {
    const std::string group = "body_" + std::to_string(b);
    if (H5Lexists(file, group.c_str(), H5P_DEFAULT) <= 0) break;
    hdf5::Handle g(H5Gopen2(file, group.c_str(), H5P_DEFAULT), H5Gclose, "open " + group);
    names.push_back(hdf5::read_string_attribute(g, "name"));
    dimensions.push_back(hdf5::read_int64_attribute(g, "dimension"));
    frame.points.push_back(dataset_rows(g, "position"));
    frame.triangles.push_back(
        H5Lexists(g, "triangles", H5P_DEFAULT) > 0 ? dataset_rows(g, "triangles") : 0);
  }
  if (H5Aexists(file, "content_hash") > 0 &&
      hdf5::read_string_attribute(file, "content_hash") !=
          frame_hash(frame.time, at, names, dimensions, hdf5::file_rows_hash(file)))
    throw std::runtime_error(path +
                             ": the content hash does not match the stored one (the frame "
                             "was changed or corrupted after it was written)");
  if (step) *step = at;
  if (bodies) *bodies = std::move(names);
  return frame;
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
  const std::string temp_path = partial_path(final_path);
  FrameRecord frame{name, sim.time(), {}, {}};
  // A shared file: every rank writes its points into it; rank 0 renames it and writes the XDMF.
  const bool shared = shared_output(sim);
  const bool root = !shared || ranks::root();
  const hdf5::SharedWrite collective(shared);  // a failure ends every rank
  hdf5::silence_errors();
  const auto& bodies = output_scene(sim).bodies;
  std::vector<std::string> names;
  std::vector<long long> dimensions;
  for (const SceneBody& sb : bodies) {
    names.push_back(sb.body.name);
    dimensions.push_back(sb.body.dimension);
  }
  try {
    Handle file(shared ? hdf5::create_shared_file(temp_path)
                       : H5Fcreate(temp_path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
                H5Fclose, "create " + temp_path);
    hdf5::write_double_attribute(file, "time", sim.time());
    hdf5::write_int64_attribute(file, "step", sim.step());
    hdf5::RowsHash rows;
    std::vector<double> buffer;
    for (std::size_t b = 0; b < bodies.size(); ++b) {
      const SceneBody& sb = bodies[b];
      Handle group(H5Gcreate2(file, ("body_" + std::to_string(b)).c_str(), H5P_DEFAULT, H5P_DEFAULT,
                              H5P_DEFAULT),
                   H5Gclose, "create a body group");
      hdf5::write_string_attribute(group, "name", sb.body.name);
      hdf5::write_int64_attribute(group, "dimension", sb.body.dimension);
      if (sb.wall && sb.wall_surface) {
        write_wall_group(group, sim, sb, b, fields_, rows);
        frame.points.push_back(sb.wall_surface->vertex.size());
        frame.triangles.push_back(sb.wall_surface->triangle.size());
      } else {
        write_point_group(group, sim, b, fields_, buffer, rows);
        frame.points.push_back(sim.whole_scene().bodies[b].body.size());
        frame.triangles.push_back(0);
      }
      group.close();
    }
    const std::uint64_t sum = shared ? ranks::sum_wrapping(rows.value()) : rows.value();
    hdf5::write_string_attribute(file, "content_hash",
                                 frame_hash(sim.time(), sim.step(), names, dimensions, sum));
    hdf5::flush_file(file, temp_path);
    file.close();
  } catch (const std::runtime_error& e) {
    std::remove(temp_path.c_str());
    throw OutputError(final_path + ": cannot write the field frame: " + e.what() +
                      "; the frames before it are complete and indexed");
  }
  if (root) {
    try {
      replace_file(temp_path, final_path, "the field frame");
    } catch (const OutputError& e) {
      if (shared) hdf5::fail(e.what());  // the other ranks went on: end every rank
      throw;
    }
  }
  frames_.push_back(std::move(frame));
  bodies_ = names;
  if (root) write_indexes();
}

void FieldWriter::write_indexes() const {
  // All in one folder: the last rename syncs it for every one.
  const std::vector<std::string> files = body_xdmf_names(bodies_);
  for (std::size_t b = 0; b < bodies_.size(); ++b)
    write_file_replacing(directory_ + "/" + files[b], body_xdmf(frames_, bodies_, b, fields_),
                         "the body's XDMF index", false);
  write_file_replacing(directory_ + "/fields.xdmf", run_xdmf(frames_, bodies_, fields_),
                       "the XDMF index");
}

}  // namespace ckpd
