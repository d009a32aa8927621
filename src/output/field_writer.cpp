#include "src/output/field_writer.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "bodies/damage.hpp"

namespace ckpd {

namespace {

// Closes an HDF5 handle when it goes out of scope.
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t), const std::string& what) : id_(id), close_(close) {
    if (id_ < 0) throw std::runtime_error("HDF5: cannot " + what);
  }
  ~Handle() { close_(id_); }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  operator hid_t() const { return id_; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

void write_dataset(hid_t group, const std::string& name, const double* data, std::size_t rows,
                   std::size_t columns) {
  const hsize_t dims[2] = {rows, columns};
  Handle space(H5Screate_simple(columns == 1 ? 1 : 2, dims, nullptr), H5Sclose, "make a dataspace");
  Handle set(
      H5Dcreate2(group, name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
      H5Dclose, "create dataset " + name);
  if (rows > 0 && H5Dwrite(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    throw std::runtime_error("HDF5: cannot write dataset " + name);
}

void write_dataset(hid_t group, const std::string& name, const std::vector<std::int32_t>& data) {
  const hsize_t dims[1] = {data.size()};
  Handle space(H5Screate_simple(1, dims, nullptr), H5Sclose, "make a dataspace");
  Handle set(
      H5Dcreate2(group, name.c_str(), H5T_STD_I32LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
      H5Dclose, "create dataset " + name);
  if (!data.empty() &&
      H5Dwrite(set, H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) < 0)
    throw std::runtime_error("HDF5: cannot write dataset " + name);
}

template <class T>
void write_attribute(hid_t object, const std::string& name, hid_t file_type, hid_t memory_type,
                     const T& value) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose, "make a dataspace");
  Handle attr(H5Acreate2(object, name.c_str(), file_type, space, H5P_DEFAULT, H5P_DEFAULT),
              H5Aclose, "create attribute " + name);
  if (H5Awrite(attr, memory_type, &value) < 0)
    throw std::runtime_error("HDF5: cannot write attribute " + name);
}

void write_string_attribute(hid_t object, const std::string& name, const std::string& value) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose, "copy a string type");
  H5Tset_size(type, std::max<std::size_t>(1, value.size()));
  Handle space(H5Screate(H5S_SCALAR), H5Sclose, "make a dataspace");
  Handle attr(H5Acreate2(object, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
              "create attribute " + name);
  if (H5Awrite(attr, type, value.c_str()) < 0)
    throw std::runtime_error("HDF5: cannot write attribute " + name);
}

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

FieldWriter::FieldWriter(std::string directory, std::vector<std::string> fields)
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
  // Frames of an earlier run in this folder must not be mixed with this run's.
  for (const auto& entry : std::filesystem::directory_iterator(directory_ + "/fields"))
    if (entry.path().extension() == ".h5") std::filesystem::remove(entry.path(), ec);
  std::filesystem::remove(directory_ + "/fields.xdmf", ec);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors are reported by exceptions instead
}

bool FieldWriter::needs_energy() const {
  return std::find(fields_.begin(), fields_.end(), "strain_energy_density") != fields_.end();
}

void FieldWriter::write_frame(const Simulation& sim) {
  std::ostringstream name;
  name << "fields/frame_" << std::setw(6) << std::setfill('0') << frames_.size() << ".h5";
  const std::string final_path = directory_ + "/" + name.str();
  const std::string temp_path = final_path + ".partial";
  Frame frame{name.str(), sim.time(), {}};
  {
    Handle file(H5Fcreate(temp_path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose,
                "create " + temp_path);
    write_attribute(file, "time", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, sim.time());
    const long long step = sim.step();
    write_attribute(file, "step", H5T_STD_I64LE, H5T_NATIVE_LLONG, step);
    const auto& bodies = sim.scene().bodies;
    std::vector<double> buffer;
    for (std::size_t b = 0; b < bodies.size(); ++b) {
      const Body& body = bodies[b].body;
      const std::size_t n = body.size();
      frame.points.push_back(n);
      Handle group(H5Gcreate2(file, ("body_" + std::to_string(b)).c_str(), H5P_DEFAULT, H5P_DEFAULT,
                              H5P_DEFAULT),
                   H5Gclose, "create a body group");
      write_string_attribute(group, "name", body.name);
      const int dimension = body.dimension;
      write_attribute(group, "dimension", H5T_STD_I32LE, H5T_NATIVE_INT, dimension);
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
          write_dataset(group, f, buffer.data(), n, 3);
        } else if (f == "damage") {
          point_damage(body, buffer);
          write_dataset(group, f, buffer.data(), n, 1);
        } else if (f == "strain_energy_density") {
          write_dataset(group, f, body.strain_energy_density.data(), n, 1);
        } else if (f == "body_id") {
          write_dataset(group, f, std::vector<std::int32_t>(n, static_cast<std::int32_t>(b)));
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
