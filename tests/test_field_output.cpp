// Field output: HDF5 frames read back with the HDF5 library, the XDMF index checked against
// them, a killed run's frames readable, and bad output settings rejected.
#include <hdf5.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <regex>
#include <sstream>
#include <thread>

#include "run_helpers.hpp"

using namespace ckpd::testing;

namespace {

// Two 2D bodies, 10 x 6 and 5 x 5 points, 20 steps, frames every 5 steps, all fields.
const char* kCase = R"(# SI units
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.3, fracture_energy: 100}
bodies:
  - {name: strip, material: steel, dimension: 2, geometry: {type: box, min: [0, 0], max: [0.01, 0.006]},
     spacing: 0.001, horizon_ratio: 3.015}
  - {name: "tile & co", material: steel, dimension: 2, geometry: {type: box, min: [0.1, 0], max: [0.105, 0.005]},
     spacing: 0.001, horizon_ratio: 2.015}
conditions:
  - {type: initial_velocity, body: strip, angular_velocity: 200, center: [0.005, 0.003], value: [1, 0]}
  - {type: initial_velocity, body: "tile & co", value: [0, -2]}
time: {steps: 20}
output: {history_interval: 5, field_interval: 5,
         fields: [position, displacement, velocity, damage, body_id, strain_energy_density, force_density]}
)";

std::vector<double> read_doubles(hid_t file, const std::string& path, std::vector<hsize_t>& dims) {
  const hid_t set = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
  REQUIRE(set >= 0);
  const hid_t space = H5Dget_space(set);
  const int rank = H5Sget_simple_extent_ndims(space);
  dims.assign(static_cast<std::size_t>(rank), 0);
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  std::size_t count = 1;
  for (auto d : dims) count *= d;
  std::vector<double> data(count);
  REQUIRE(H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) >= 0);
  H5Sclose(space);
  H5Dclose(set);
  return data;
}

template <class T>
T read_attribute(hid_t object, const char* name, hid_t type) {
  T value{};
  const hid_t attr = H5Aopen(object, name, H5P_DEFAULT);
  REQUIRE(attr >= 0);
  REQUIRE(H5Aread(attr, type, &value) >= 0);
  H5Aclose(attr);
  return value;
}

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Every DataItem of the XDMF names a dataset of an existing frame file with its shape.
int check_xdmf_against_hdf5(const std::filesystem::path& out) {
  const std::string xdmf = slurp(out / "fields.xdmf");
  const std::regex item(
      R"re(<DataItem Dimensions="([0-9 ]+)"[^>]*Format="HDF">([^:<]+):([^<]+)</DataItem>)re");
  int items = 0;
  for (std::sregex_iterator it(xdmf.begin(), xdmf.end(), item), end; it != end; ++it, ++items) {
    const std::string dims_text = (*it)[1], file = (*it)[2], path = (*it)[3];
    INFO(file << ":" << path);
    const hid_t h5 = H5Fopen((out / file).c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    REQUIRE(h5 >= 0);
    const hid_t set = H5Dopen2(h5, path.c_str(), H5P_DEFAULT);
    REQUIRE(set >= 0);
    const hid_t space = H5Dget_space(set);
    std::vector<hsize_t> dims(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space)));
    H5Sget_simple_extent_dims(space, dims.data(), nullptr);
    std::ostringstream shape;
    for (std::size_t d = 0; d < dims.size(); ++d) shape << (d ? " " : "") << dims[d];
    CHECK(shape.str() == dims_text);
    H5Sclose(space);
    H5Dclose(set);
    H5Fclose(h5);
  }
  return items;
}

}  // namespace

TEST_CASE("field frames read back with every field, and the XDMF matches them", "[output]") {
  const auto dir = fresh_dir("fields");
  const std::string file = write_file(dir / "case.yaml", kCase);
  const auto out = dir / "out";
  const CommandResult r = run_ckpd("run " + file + " --quiet --out " + out.string());
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  const auto summary = read_json(out / "summary.json");
  const double dt = summary["dt"];
  CHECK(summary["field_frames"] == 5);

  // History rows (every 5 steps) carry the strain energy the frames must add up to.
  std::map<long long, double> strain_by_step;
  {
    std::ifstream history(out / "history.csv");
    std::string line;
    std::getline(history, line);
    while (std::getline(history, line)) {
      std::stringstream row(line);
      std::string step, time, kinetic, strain;
      std::getline(row, step, ',');
      std::getline(row, time, ',');
      std::getline(row, kinetic, ',');
      std::getline(row, strain, ',');
      strain_by_step[std::stoll(step)] = std::stod(strain);
    }
  }

  const std::size_t points[2] = {60, 25};
  for (int frame = 0; frame < 5; ++frame) {
    std::ostringstream name;
    name << "fields/frame_" << std::setw(6) << std::setfill('0') << frame << ".h5";
    INFO(name.str());
    const hid_t h5 = H5Fopen((out / name.str()).c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    REQUIRE(h5 >= 0);
    const long long step = read_attribute<long long>(h5, "step", H5T_NATIVE_LLONG);
    const double time = read_attribute<double>(h5, "time", H5T_NATIVE_DOUBLE);
    CHECK(step == 5 * frame);
    CHECK(time == Approx(static_cast<double>(step) * dt).margin(1e-15));
    double strain = 0;
    for (int b = 0; b < 2; ++b) {
      const std::string g = "/body_" + std::to_string(b) + "/";
      std::vector<hsize_t> dims;
      const auto position = read_doubles(h5, g + "position", dims);
      CHECK(dims == std::vector<hsize_t>{points[b], 3});
      const auto displacement = read_doubles(h5, g + "displacement", dims);
      CHECK(dims == std::vector<hsize_t>{points[b], 3});
      const auto velocity = read_doubles(h5, g + "velocity", dims);
      CHECK(dims == std::vector<hsize_t>{points[b], 3});
      const auto force = read_doubles(h5, g + "force_density", dims);
      CHECK(dims == std::vector<hsize_t>{points[b], 3});
      const auto damage = read_doubles(h5, g + "damage", dims);
      CHECK(dims == std::vector<hsize_t>{points[b]});
      const auto energy = read_doubles(h5, g + "strain_energy_density", dims);
      CHECK(dims == std::vector<hsize_t>{points[b]});
      const auto ids = read_doubles(h5, g + "body_id", dims);
      for (double id : ids) CHECK(id == b);
      for (double d : damage) CHECK((d >= 0 && d <= 1));
      // position - displacement is the reference lattice: cell centres 1 mm apart, z = 0.
      const double x0 = b == 0 ? 0.0005 : 0.1005;
      for (std::size_t i = 0; i < points[b]; ++i) {
        const double X = position[3 * i] - displacement[3 * i];
        const double Y = position[3 * i + 1] - displacement[3 * i + 1];
        const double cells_x = (X - x0) / 0.001, cells_y = (Y - 0.0005) / 0.001;
        CHECK(std::abs(cells_x - std::round(cells_x)) < 1e-6);
        CHECK(std::abs(cells_y - std::round(cells_y)) < 1e-6);
        CHECK(position[3 * i + 2] == 0);
      }
      // Initial velocities as set; later the rigid parts persist on average.
      if (frame == 0) {
        const double expect_vy = b == 0 ? 200 * (position[0] - 0.005) : -2.0;
        CHECK(velocity[1] == Approx(expect_vy).margin(1e-12));
      }
      for (std::size_t i = 0; i < points[b]; ++i) strain += energy[i] * 1e-6;  // V = dx^2
      const hid_t group = H5Gopen2(h5, g.c_str(), H5P_DEFAULT);
      CHECK(read_attribute<long long>(group, "dimension", H5T_NATIVE_LLONG) == 2);
      H5Gclose(group);
    }
    CHECK(strain == Approx(strain_by_step.at(step)).epsilon(1e-9));
    H5Fclose(h5);
  }
  CHECK(check_xdmf_against_hdf5(out) == 5 * 2 * 8);  // 7 fields and the connectivity
  // Well-formed XML, and the body names survive escaping.
  const CommandResult xml =
      CommandResult{std::system(("python3 -c \"import xml.etree.ElementTree as E; E.parse('" +
                                 (out / "fields.xdmf").string() + "')\"")
                                    .c_str()),
                    ""};
  CHECK(xml.exit_code == 0);
  CHECK(slurp(out / "fields.xdmf").find("Name=\"tile &amp; co\"") != std::string::npos);
}

TEST_CASE("no field output is asked for, so no field file is written", "[output]") {
  const auto dir = fresh_dir("nofields");
  std::string text = kCase;
  text = text.substr(0, text.find("output:")) + "output: {history_interval: 5}\n";
  const std::string file = write_file(dir / "case.yaml", text);
  const CommandResult r = run_ckpd("run " + file + " --quiet --out " + (dir / "out").string());
  REQUIRE(r.exit_code == 0);
  CHECK_FALSE(std::filesystem::exists(dir / "out" / "fields.xdmf"));
  CHECK_FALSE(std::filesystem::exists(dir / "out" / "fields"));
}

TEST_CASE("a run killed mid-way leaves every complete frame readable", "[output]") {
  const auto dir = fresh_dir("killed");
  std::string text = kCase;
  text.replace(text.find("time: {steps: 20}"), 17, "time: {steps: 100000000}");
  text.replace(text.find("field_interval: 5"), 17, "field_interval: 50");
  const std::string file = write_file(dir / "case.yaml", text);
  const auto out = dir / "out";
  run_ckpd("run " + file + " --quiet --out " + out.string() + " & pid=$!; sleep 3; kill -9 $pid");
  // The command above returns when the shell does; wait for the kill to land.
  std::this_thread::sleep_for(std::chrono::seconds(4));
  REQUIRE(std::filesystem::exists(out / "fields.xdmf"));
  CHECK_FALSE(std::filesystem::exists(out / "summary.json"));  // never passes for complete
  const int items = check_xdmf_against_hdf5(out);
  // Per frame and body: the 7 fields and the Polyvertex connectivity.
  CHECK(items >= 2 * 8);
  CHECK(items % 16 == 0);
  // A frame is renamed into place, then listed in the XDMF: a kill between the two leaves one
  // complete frame that the XDMF does not list yet, never more (a frame still being written
  // has the .partial extension).
  std::size_t frame_files = 0;
  for (const auto& e : std::filesystem::directory_iterator(out / "fields"))
    frame_files += e.path().extension() == ".h5";
  const auto listed = static_cast<std::size_t>(items / 16);
  CHECK(frame_files >= listed);
  CHECK(frame_files <= listed + 1);
}

TEST_CASE("bad output settings are rejected before anything is written", "[output]") {
  const auto dir = fresh_dir("badout");
  std::string text = kCase;
  text.replace(text.find("damage, body_id"), 15, "damage, bodyid");
  std::string file = write_file(dir / "case.yaml", text);
  CommandResult r = run_ckpd("run " + file + " --quiet --out " + (dir / "out").string());
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("output.fields[4]") != std::string::npos);
  CHECK(r.output.find("a field name") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir / "out"));

  file = write_file(dir / "good.yaml", kCase);
  write_file(dir / "occupied", "a file where the output folder should go");
  r = run_ckpd("run " + file + " --quiet --out " + (dir / "occupied").string());
  CHECK(r.exit_code != 0);
  CHECK(r.output.find("cannot create the output directory") != std::string::npos);
}
