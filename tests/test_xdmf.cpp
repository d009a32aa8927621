// The XDMF index parsed as XML (libxml2) and checked as ParaView's readers read it: every grid
// has a topology with explicit connectivity (Polyvertex 0..N-1 for points, the wall's
// triangles for a mesh wall), every heavy-data path resolves relative to the XDMF file to a
// dataset of the stated shape, times match the frames, and a mesh wall's surface moves with
// its rigid motion.
#include <hdf5.h>
#include <libxml/parser.h>
#include <libxml/tree.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "run_helpers.hpp"

using namespace ckpd::testing;

namespace {

std::string attribute(xmlNode* node, const char* name) {
  xmlChar* v = xmlGetProp(node, reinterpret_cast<const xmlChar*>(name));
  if (!v) return "";
  std::string s(reinterpret_cast<const char*>(v));
  xmlFree(v);
  return s;
}

std::string text(xmlNode* node) {
  xmlChar* v = xmlNodeGetContent(node);
  std::string s(reinterpret_cast<const char*>(v));
  xmlFree(v);
  return s;
}

std::vector<xmlNode*> children(xmlNode* node, const std::string& name) {
  std::vector<xmlNode*> out;
  for (xmlNode* c = node->children; c; c = c->next)
    if (c->type == XML_ELEMENT_NODE && name == reinterpret_cast<const char*>(c->name))
      out.push_back(c);
  return out;
}

xmlNode* child(xmlNode* node, const std::string& name) {
  const auto all = children(node, name);
  REQUIRE(all.size() == 1);
  return all[0];
}

// A DataItem's HDF dataset read as doubles, after checking its shape against Dimensions.
struct Item {
  std::vector<std::size_t> dims;
  std::vector<double> values;
};
Item read_item(xmlNode* item, const std::filesystem::path& xdmf_dir) {
  REQUIRE(attribute(item, "Format") == "HDF");
  const std::string ref = text(item);
  const auto colon = ref.find(':');
  REQUIRE(colon != std::string::npos);
  const std::filesystem::path file = ref.substr(0, colon);
  CHECK(file.is_relative());
  const std::string dataset = ref.substr(colon + 1);
  INFO(ref);
  const hid_t h5 = H5Fopen((xdmf_dir / file).c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  REQUIRE(h5 >= 0);
  const hid_t set = H5Dopen2(h5, dataset.c_str(), H5P_DEFAULT);
  REQUIRE(set >= 0);
  const hid_t space = H5Dget_space(set);
  std::vector<hsize_t> dims(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space)));
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  Item out;
  std::stringstream stated(attribute(item, "Dimensions"));
  for (std::size_t d; stated >> d;) out.dims.push_back(d);
  REQUIRE(out.dims == std::vector<std::size_t>(dims.begin(), dims.end()));
  std::size_t count = 1;
  for (auto d : dims) count *= d;
  out.values.resize(count);
  REQUIRE(H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.values.data()) >= 0);
  // The number type stated must be the stored one (ParaView reads the bytes as stated).
  const hid_t type = H5Dget_type(set);
  const bool integer = H5Tget_class(type) == H5T_INTEGER;
  CHECK(attribute(item, "NumberType") == (integer ? "Int" : "Float"));
  CHECK(attribute(item, "Precision") == std::to_string(H5Tget_size(type)));
  H5Tclose(type);
  H5Sclose(space);
  H5Dclose(set);
  H5Fclose(h5);
  return out;
}

}  // namespace

TEST_CASE("the XDMF is well-formed XML whose grids all have connectivity and resolvable data",
          "[output][xdmf]") {
  const auto dir = fresh_dir("xdmf");
  // A block and a moving mesh-wall floor (the case file says more).
  const std::string file = CKPD_SOURCE_DIR "/tests/data/block_and_floor/case.yaml";
  const auto out = dir / "out";
  const CommandResult r = run_ckpd("run " + file + " --quiet --out " + out.string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const double dt = read_json(out / "summary.json")["dt"];

  xmlDoc* doc = xmlReadFile((out / "fields.xdmf").c_str(), nullptr, XML_PARSE_NONET);
  REQUIRE(doc != nullptr);
  xmlNode* root = xmlDocGetRootElement(doc);
  CHECK(std::string(reinterpret_cast<const char*>(root->name)) == "Xdmf");
  xmlNode* series = child(child(root, "Domain"), "Grid");
  CHECK(attribute(series, "CollectionType") == "Temporal");
  const auto frames = children(series, "Grid");
  REQUIRE(frames.size() == 4);  // steps 0, 4, 8, 12
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const double time = std::stod(attribute(child(frames[f], "Time"), "Value"));
    CHECK(time == Approx(4.0 * dt * static_cast<double>(f)).epsilon(1e-12));
    const auto grids = children(frames[f], "Grid");
    REQUIRE(grids.size() == 2);
    for (xmlNode* grid : grids) {
      const std::string name = attribute(grid, "Name");
      INFO("frame " << f << ", grid " << name);
      xmlNode* topology = child(grid, "Topology");
      const Item cells = read_item(child(topology, "DataItem"), out);
      const Item x = read_item(child(child(grid, "Geometry"), "DataItem"), out);
      REQUIRE(x.dims.size() == 2);
      const std::size_t nodes = x.dims[0];
      const std::size_t elements = std::stoul(attribute(topology, "NumberOfElements"));
      const std::size_t per_element = std::stoul(attribute(topology, "NodesPerElement"));
      CHECK(cells.values.size() == elements * per_element);
      for (double v : cells.values) CHECK((v >= 0 && v < static_cast<double>(nodes)));
      std::map<std::string, Item> fields;
      for (xmlNode* a : children(grid, "Attribute")) {
        CHECK(attribute(a, "Center") == "Node");
        Item item = read_item(child(a, "DataItem"), out);
        CHECK(item.dims[0] == nodes);
        fields[attribute(a, "Name")] = item;
      }
      if (name == "block") {
        CHECK(attribute(topology, "TopologyType") == "Polyvertex");
        CHECK(nodes == 18);
        CHECK(per_element == 1);
        for (std::size_t i = 0; i < nodes; ++i) CHECK(cells.values[i] == i);
        for (const char* expected :
             {"displacement", "reference_position", "point_id", "volume", "body_id", "damage"})
          CHECK(fields.count(expected) == 1);
        for (std::size_t i = 0; i < nodes; ++i) {
          CHECK(fields["point_id"].values[i] == i);
          CHECK(fields["body_id"].values[i] == 0);
          CHECK(fields["volume"].values[i] == Approx(1e-9).epsilon(1e-12));
          for (int k = 0; k < 3; ++k)
            CHECK(x.values[3 * i + k] == Approx(fields["reference_position"].values[3 * i + k] +
                                                fields["displacement"].values[3 * i + k])
                                             .margin(1e-15));
        }
      } else {
        // The wall: its triangles, and its vertices where its rigid motion has taken them.
        CHECK(name == "floor");
        CHECK(attribute(topology, "TopologyType") == "Triangle");
        CHECK(elements == 2);
        CHECK(nodes == 4);
        CHECK(fields.count("volume") == 0);  // a point field: not on a surface
        const Item& X = fields.at("reference_position");
        const double angle = 1000 * time, shift = 2 * time;
        for (std::size_t v = 0; v < nodes; ++v) {
          const double X0 = X.values[3 * v], Y0 = X.values[3 * v + 1];
          CHECK(x.values[3 * v] ==
                Approx(shift + std::cos(angle) * X0 - std::sin(angle) * Y0).margin(1e-9));
          CHECK(x.values[3 * v + 1] ==
                Approx(std::sin(angle) * X0 + std::cos(angle) * Y0).margin(1e-9));
          CHECK(x.values[3 * v + 2] == Approx(0).margin(1e-12));
        }
      }
    }
  }
  xmlFreeDoc(doc);
}
