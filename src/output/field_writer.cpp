#include "src/output/field_writer.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "bodies/damage.hpp"
#include "src/output/hdf5_io.hpp"

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

bool is_vector_field(const std::string& name) {
  return name == "position" || name == "displacement" || name == "velocity" ||
         name == "force_density";
}

}  // namespace

const std::vector<std::string>& known_field_names() {
  static const std::vector<std::string> names{
      "position", "displacement",          "velocity",     "damage",
      "body_id",  "strain_energy_density", "force_density"};
  return names;
}

FieldWriter::FieldWriter(std::string directory, std::vector<std::string> fields,
                         long long resume_after_step)
    : directory_(std::move(directory)) {
  fields_.push_back("position");
  for (const std::string& f : fields) {
    const auto& known = known_field_names();
    if (std::find(known.begin(), known.end(), f) == known.end()) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      throw std::invalid_argument("unknown output field '" + f + "' (known: " + list + ")");
    }
    if (std::find(fields_.begin(), fields_.end(), f) == fields_.end()) fields_.push_back(f);
  }
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
          Frame frame{
              "fields/" + path.filename().string(), hdf5::read_double_attribute(file, "time"), {}};
          for (long long b = 0;; ++b) {
            const std::string group = "body_" + std::to_string(b);
            if (H5Lexists(file, group.c_str(), H5P_DEFAULT) <= 0) break;
            hdf5::Handle g(H5Gopen2(file, group.c_str(), H5P_DEFAULT), H5Gclose, "open " + group);
            hdf5::Handle set(H5Dopen2(g, "position", H5P_DEFAULT), H5Dclose, "open position");
            hdf5::Handle space(H5Dget_space(set), H5Sclose, "read a shape");
            frame.points.push_back(
                static_cast<std::size_t>(H5Sget_simple_extent_npoints(space) / 3));
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
  return std::find(fields_.begin(), fields_.end(), "strain_energy_density") != fields_.end();
}

void FieldWriter::write_frame(const Simulation& sim) {
  const std::string name = "fields/" + frame_name(frames_.size());
  const std::string final_path = directory_ + "/" + name;
  const std::string temp_path = final_path + ".partial";
  Frame frame{name, sim.time(), {}};
  {
    Handle file(H5Fcreate(temp_path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose,
                "create " + temp_path);
    hdf5::write_double_attribute(file, "time", sim.time());
    hdf5::write_int64_attribute(file, "step", sim.step());
    const auto& bodies = sim.scene().bodies;
    std::vector<double> buffer;
    for (std::size_t b = 0; b < bodies.size(); ++b) {
      const Body& body = bodies[b].body;
      const std::size_t n = body.size();
      frame.points.push_back(n);
      Handle group(H5Gcreate2(file, ("body_" + std::to_string(b)).c_str(), H5P_DEFAULT, H5P_DEFAULT,
                              H5P_DEFAULT),
                   H5Gclose, "create a body group");
      hdf5::write_string_attribute(group, "name", body.name);
      hdf5::write_int64_attribute(group, "dimension", body.dimension);
      for (const std::string& f : fields_) {
        if (is_vector_field(f)) {
          const std::vector<Vec3>* v = f == "displacement"    ? &body.displacement
                                       : f == "velocity"      ? &body.velocity
                                       : f == "force_density" ? &body.force_density
                                                              : nullptr;
          buffer.resize(3 * n);
          for (std::size_t i = 0; i < n; ++i) {
            const Vec3 x = v ? (*v)[i] : body.current_position(i);
            buffer[3 * i] = x.x();
            buffer[3 * i + 1] = x.y();
            buffer[3 * i + 2] = x.z();
          }
          hdf5::write_doubles(group, f, buffer.data(), n, 3);
        } else if (f == "damage") {
          point_damage(body, buffer);
          hdf5::write_doubles(group, f, buffer.data(), n, 1);
        } else if (f == "strain_energy_density") {
          hdf5::write_doubles(group, f, body.strain_energy_density.data(), n, 1);
        } else if (f == "body_id") {
          hdf5::write_int32(group, f, std::vector<std::int32_t>(n, static_cast<std::int32_t>(b)));
        }
      }
    }
    if (H5Fflush(file, H5F_SCOPE_GLOBAL) < 0)
      throw std::runtime_error("HDF5: cannot flush " + temp_path);
  }
  std::error_code ec;
  std::filesystem::rename(temp_path, final_path, ec);
  if (ec) throw std::runtime_error(final_path + ": cannot write: " + ec.message());
  frames_.push_back(std::move(frame));
  write_xdmf(sim);
}

void FieldWriter::write_xdmf(const Simulation& sim) const {
  const std::string path = directory_ + "/fields.xdmf";
  const std::string temp = path + ".partial";
  {
    std::ofstream x(temp);
    x << std::setprecision(17);
    x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n <Domain>\n"
      << "  <Grid Name=\"run\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    const auto& bodies = sim.scene().bodies;
    for (const Frame& frame : frames_) {
      x << "   <Grid Name=\"" << frame.file << "\" GridType=\"Collection\" "
        << "CollectionType=\"Spatial\">\n    <Time Value=\"" << frame.time << "\"/>\n";
      for (std::size_t b = 0; b < bodies.size(); ++b) {
        const std::size_t n = frame.points[b];
        const std::string h5 = frame.file + ":/body_" + std::to_string(b) + "/";
        auto item = [&](const std::string& field, bool vector, const char* type) {
          x << "      <DataItem Dimensions=\"" << n << (vector ? " 3" : "") << "\" NumberType=\""
            << type << "\" Precision=\"" << (std::string(type) == "Int" ? 4 : 8)
            << "\" Format=\"HDF\">" << h5 << field << "</DataItem>\n";
        };
        x << "    <Grid Name=\"" << xml_escape(bodies[b].body.name) << "\" GridType=\"Uniform\">\n"
          << "     <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n
          << "\" NodesPerElement=\"1\"/>\n     <Geometry GeometryType=\"XYZ\">\n";
        item("position", true, "Float");
        x << "     </Geometry>\n";
        for (const std::string& f : fields_) {
          if (f == "position") continue;
          const bool vector = is_vector_field(f);
          x << "     <Attribute Name=\"" << f << "\" AttributeType=\""
            << (vector ? "Vector" : "Scalar") << "\" Center=\"Node\">\n";
          item(f, vector, f == "body_id" ? "Int" : "Float");
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
