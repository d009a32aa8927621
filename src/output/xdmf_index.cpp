#include "src/output/xdmf_index.hpp"

#include <algorithm>
#include <cctype>
#include <iomanip>
#include <sstream>

#include "src/output/field_table.hpp"

namespace ckpd {

namespace {

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

// The fields a mesh wall's surface carries (its vertices move rigidly; the rest are point
// fields of deformable bodies).
bool wall_field(const std::string& name) {
  return name == "position" || name == "reference_position" || name == "displacement" ||
         name == "body_id" || name == "point_id";
}

// Body b of one frame as a Uniform grid with `indent` spaces; `position_attribute`: the position
// also as point data (meshio reads the geometry of the first frame only).
void body_grid(std::ostream& x, const FrameRecord& frame, const std::string& name, std::size_t b,
               const std::vector<std::string>& fields, const std::string& indent, bool with_time,
               bool position_attribute) {
  const std::size_t n = frame.points[b];
  const std::size_t triangles = frame.triangles[b];
  const std::string h5 = frame.file + ":/body_" + std::to_string(b) + "/";
  auto item = [&](const std::string& dataset, std::size_t rows, int columns, FieldNumber number) {
    const bool integer = number == FieldNumber::int32;
    x << indent << "   <DataItem Dimensions=\"" << rows;
    if (columns > 1) x << " " << columns;
    x << "\" NumberType=\"" << (integer ? "Int" : "Float") << "\" Precision=\"" << (integer ? 4 : 8)
      << "\" Format=\"HDF\">" << h5 << dataset << "</DataItem>\n";
  };
  x << indent << "<Grid Name=\"" << xml_escape(name) << "\" GridType=\"Uniform\">\n";
  if (with_time) x << indent << " <Time Value=\"" << frame.time << "\"/>\n";
  if (triangles > 0) {
    x << indent << " <Topology TopologyType=\"Triangle\" NumberOfElements=\"" << triangles
      << "\" NodesPerElement=\"3\">\n";
    item("triangles", triangles, 3, FieldNumber::int32);
  } else {
    x << indent << " <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"" << n
      << "\" NodesPerElement=\"1\">\n";
    item("connectivity", n, 1, FieldNumber::int32);
  }
  x << indent << " </Topology>\n" << indent << " <Geometry GeometryType=\"XYZ\">\n";
  item("position", n, 3, FieldNumber::float64);
  x << indent << " </Geometry>\n";
  for (const std::string& f : fields) {
    if ((f == "position" && !position_attribute) || (triangles > 0 && !wall_field(f))) continue;
    const FieldSpec& spec = *find_field(f);
    x << indent << " <Attribute Name=\"" << f << "\" AttributeType=\""
      << xdmf_attribute_type(spec.components) << "\" Center=\"Node\">\n";
    item(f, n, spec.components, spec.number);
    x << indent << " </Attribute>\n";
  }
  x << indent << "</Grid>\n";
}

const char* kHead = "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n <Domain>\n";
const char* kTail = " </Domain>\n</Xdmf>\n";

}  // namespace

std::string run_xdmf(const std::vector<FrameRecord>& frames, const std::vector<std::string>& bodies,
                     const std::vector<std::string>& fields) {
  std::ostringstream x;
  x << std::setprecision(17) << kHead
    << "  <Grid Name=\"run\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const FrameRecord& frame : frames) {
    x << "   <Grid Name=\"" << frame.file << "\" GridType=\"Collection\" "
      << "CollectionType=\"Spatial\">\n    <Time Value=\"" << frame.time << "\"/>\n";
    for (std::size_t b = 0; b < bodies.size(); ++b)
      body_grid(x, frame, bodies[b], b, fields, "    ", false, false);
    x << "   </Grid>\n";
  }
  x << "  </Grid>\n" << kTail;
  return x.str();
}

std::string body_xdmf(const std::vector<FrameRecord>& frames,
                      const std::vector<std::string>& bodies, std::size_t b,
                      const std::vector<std::string>& fields) {
  std::ostringstream x;
  x << std::setprecision(17) << kHead << "  <Grid Name=\"" << xml_escape(bodies[b])
    << "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (const FrameRecord& frame : frames)
    body_grid(x, frame, bodies[b], b, fields, "   ", true, true);
  x << "  </Grid>\n" << kTail;
  return x.str();
}

std::vector<std::string> body_xdmf_names(const std::vector<std::string>& bodies) {
  std::vector<std::string> stems;
  for (const std::string& name : bodies) {
    std::string stem = name;
    for (char& c : stem)
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') c = '_';
    stems.push_back(stem);
  }
  std::vector<std::string> names;
  for (std::size_t b = 0; b < stems.size(); ++b) {
    const bool shared = std::count(stems.begin(), stems.end(), stems[b]) > 1;
    names.push_back("fields_" + stems[b] + (shared ? "_" + std::to_string(b) : "") + ".xdmf");
  }
  return names;
}

}  // namespace ckpd
