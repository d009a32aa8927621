// Checkpoint integrity (issue 18): a content hash over every dataset and counter, value checks
// on restore (bond flags, finiteness, step against time), and a case mismatch that names the
// key. Each damaged checkpoint is refused with exit 2 and a message naming what failed.
#include <hdf5.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "run_helpers.hpp"
#include "src/output/hdf5_io.hpp"

using namespace ckpd::testing;

namespace {

const char* kCase = R"(# SI units
materials:
  steel: {density: 7850, youngs_modulus: 200e9, poisson_ratio: 0.2, fracture_energy: 50}
bodies:
  - name: strip
    material: steel
    dimension: 2
    geometry: {type: box, min: [0, 0], max: [0.02, 0.01]}
    spacing: 0.001
    horizon_ratio: 3.015
conditions:
  - {type: velocity, body: strip, region: {type: box, min: [0, 0.008], max: [0.02, 0.01]}, value: [0, 2], components: [y]}
time: {steps: 10}
output: {history_interval: 5}
)";

struct Fixture {
  std::filesystem::path dir;
  std::string file;
  std::filesystem::path checkpoint;
};

// A 10-step run interrupted by nothing: `checkpoint_interval: 10` leaves its checkpoint.
Fixture make_checkpoint(const std::string& tag) {
  Fixture f;
  f.dir = fresh_dir(tag);
  f.file = write_file(f.dir / "case.yaml", kCase);
  const CommandResult r =
      run_ckpd("run " + f.file + " --quiet --set output.checkpoint_interval=10 --out " +
               (f.dir / "a").string());
  REQUIRE(r.exit_code == 0);
  f.checkpoint = f.dir / "a" / "checkpoint.h5";
  REQUIRE(std::filesystem::exists(f.checkpoint));
  return f;
}

// Restarts from `checkpoint` with 5 more steps; expects exit 2, the fragments, no summary.
CommandResult expect_refused(const Fixture& f, const std::filesystem::path& checkpoint,
                             std::initializer_list<std::string> fragments,
                             const std::string& extra = "") {
  const auto out = f.dir / ("restart-" + checkpoint.stem().string());
  const CommandResult r = run_ckpd("run " + f.file + " --quiet --set time.steps=15 " + extra +
                                   " --out " + out.string() + " --restart " + checkpoint.string());
  INFO(r.output);
  CHECK(r.exit_code == 2);
  for (const std::string& s : fragments) CHECK(r.output.find(s) != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(out / "summary.json"));
  return r;
}

std::filesystem::path copy_of(const Fixture& f, const std::string& name) {
  const auto to = f.dir / name;
  std::filesystem::copy_file(f.checkpoint, to);
  return to;
}

// Writes `value` into element `index` of a dataset of the checkpoint through HDF5 (a change
// that HDF5 reads back without complaint: only ckpd's own checks can catch it).
template <class T>
void poke(const std::filesystem::path& file, const char* dataset, hid_t type, std::size_t index,
          T value) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  REQUIRE(f >= 0);
  const hid_t d = H5Dopen2(f, dataset, H5P_DEFAULT);
  REQUIRE(d >= 0);
  const hid_t space = H5Dget_space(d);
  const int rank = H5Sget_simple_extent_ndims(space);
  hsize_t dims[2] = {0, 0};
  H5Sget_simple_extent_dims(space, dims, nullptr);
  const std::size_t total = rank == 2 ? dims[0] * dims[1] : dims[0];
  std::vector<T> data(total);
  REQUIRE(H5Dread(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) >= 0);
  data[index] = value;
  REQUIRE(H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) >= 0);
  H5Sclose(space);
  H5Dclose(d);
  H5Fclose(f);
}

// The file offset and size of a contiguous dataset's data.
std::pair<haddr_t, hsize_t> data_region(const std::filesystem::path& file, const char* dataset) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, dataset, H5P_DEFAULT);
  const haddr_t offset = H5Dget_offset(d);
  const hsize_t size = H5Dget_storage_size(d);
  H5Dclose(d);
  H5Fclose(f);
  return {offset, size};
}

// FNV-1a (64 bit), written out here from its definition: the reference for the format-3 hash.
struct Fnv {
  std::uint64_t h = 1469598103934665603ull;
  void bytes(const void* data, std::size_t size) {
    for (std::size_t i = 0; i < size; ++i) {
      h ^= static_cast<const unsigned char*>(data)[i];
      h *= 1099511628211ull;
    }
  }
  template <class T>
  void value(T v) {
    bytes(&v, sizeof v);
  }
};

// Turns a checkpoint of the strip case into the format ckpd wrote before format 4: the same
// datasets, "ckpd checkpoint 3" and the hash of the counters and then each body's name, initially
// failed bonds and arrays (each array its length, then its bytes) in one sequence.
void make_format_3(const std::filesystem::path& file) {
  namespace h5 = ckpd::hdf5;
  h5::Handle f(H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose, "open");
  Fnv h;
  h.value(h5::read_double_attribute(f, "dt"));
  h.value(h5::read_double_attribute(f, "time"));
  h.value(h5::read_int64_attribute(f, "step"));
  for (const char* name : {"external_work", "dissipated", "strain_energy", "initial_total"})
    h.value(h5::read_double_attribute(f, name));
  {
    h5::Handle body(H5Gopen2(f, "body_0", H5P_DEFAULT), H5Gclose, "open body_0");
    const std::string name = "strip";
    h.value(name.size());
    h.bytes(name.data(), name.size());
    h.value(static_cast<std::size_t>(h5::read_int64_attribute(body, "initially_failed")));
    const auto n = static_cast<std::size_t>(h5::read_int64_attribute(body, "points"));
    for (const char* set :
         {"displacement", "velocity", "acceleration", "force_density", "external_force_density"}) {
      const std::vector<ckpd::Vec3> v = h5::read_vectors(body, set, n);
      h.value(v.size());
      h.bytes(v.data(), v.size() * sizeof(ckpd::Vec3));
    }
    const std::vector<double> sed = h5::read_doubles(body, "strain_energy_density", n);
    h.value(sed.size());
    h.bytes(sed.data(), sed.size() * sizeof(double));
    h5::Handle set(H5Dopen2(body, "bond_intact", H5P_DEFAULT), H5Dclose, "open bond_intact");
    h5::Handle space(H5Dget_space(set), H5Sclose, "read a shape");
    const std::vector<std::uint8_t> bonds = h5::read_bytes(
        body, "bond_intact", static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
    h.value(bonds.size());
    h.bytes(bonds.data(), bonds.size());
  }
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h.h));
  for (const char* name : {"format", "content_hash"}) H5Adelete(f, name);
  h5::write_string_attribute(f, "format", "ckpd checkpoint 3");
  h5::write_string_attribute(f, "content_hash", hex);
}

}  // namespace

TEST_CASE("a restart from an untouched checkpoint is accepted", "[checkpoint]") {
  const Fixture f = make_checkpoint("ckpt-good");
  const CommandResult r = run_ckpd("run " + f.file + " --quiet --set time.steps=15 --out " +
                                   (f.dir / "b").string() + " --restart " + f.checkpoint.string());
  INFO(r.output);
  CHECK(r.exit_code == 0);
}

TEST_CASE("a byte flipped in any dataset's data is refused by the content hash", "[checkpoint]") {
  const Fixture f = make_checkpoint("ckpt-flip");
  int k = 0;
  for (const char* dataset :
       {"/body_0/displacement", "/body_0/velocity", "/body_0/acceleration", "/body_0/force_density",
        "/body_0/external_force_density", "/body_0/strain_energy_density", "/body_0/bond_intact"}) {
    const auto [offset, size] = data_region(f.checkpoint, dataset);
    REQUIRE(offset != HADDR_UNDEF);
    REQUIRE(size > 0);
    // Deterministic positions: the first, a middle and the last byte, each with a different bit.
    for (const hsize_t at : {hsize_t{0}, size / 2, size - 1}) {
      const auto copy = copy_of(f, "flip" + std::to_string(k++) + ".h5");
      {
        std::fstream io(copy, std::ios::in | std::ios::out | std::ios::binary);
        io.seekg(static_cast<std::streamoff>(offset + at));
        char c = 0;
        io.get(c);
        // bond_intact holds 0 and 1: flip bit 0 there, so the flag stays in range and only the
        // hash can tell.
        c ^=
            std::string(dataset) == "/body_0/bond_intact" ? 0x01 : static_cast<char>(1 << (at % 7));
        io.seekp(static_cast<std::streamoff>(offset + at));
        io.put(c);
      }
      INFO(dataset << " byte " << at);
      expect_refused(f, copy, {copy.string(), "corrupted"});
    }
  }
}

TEST_CASE("a bond flag of 7 is refused naming the flag", "[checkpoint]") {
  const Fixture f = make_checkpoint("ckpt-flag");
  const auto copy = copy_of(f, "flag7.h5");
  poke<std::uint8_t>(copy, "/body_0/bond_intact", H5T_NATIVE_UINT8, 3, 7);
  expect_refused(f, copy, {"body 'strip'", "bond_intact[3] = 7", "not 0 (broken) or 1 (intact)"});
}

TEST_CASE("a NaN displacement is refused naming the point", "[checkpoint]") {
  const Fixture f = make_checkpoint("ckpt-nan");
  const auto copy = copy_of(f, "nan.h5");
  poke<double>(copy, "/body_0/displacement", H5T_NATIVE_DOUBLE, 3 * 5 + 1,
               std::numeric_limits<double>::quiet_NaN());
  expect_refused(f, copy, {"body 'strip'", "the displacement of point 5 is not finite"});
}

TEST_CASE("a step of 1e15 that disagrees with the time is refused", "[checkpoint]") {
  const Fixture f = make_checkpoint("ckpt-step");
  const auto copy = copy_of(f, "step.h5");
  {
    const hid_t file = H5Fopen(copy.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    const hid_t a = H5Aopen(file, "step", H5P_DEFAULT);
    const long long step = 1'000'000'000'000'000LL;
    REQUIRE(H5Awrite(a, H5T_NATIVE_LLONG, &step) >= 0);
    H5Aclose(a);
    H5Fclose(file);
  }
  expect_refused(f, copy, {"step 1000000000000000", "do not agree with dt"});
}

TEST_CASE("a checkpoint of another case names the key that differs", "[checkpoint]") {
  const Fixture f = make_checkpoint("ckpt-case");
  expect_refused(f, f.checkpoint,
                 {"another case",
                  "materials.steel.youngs_modulus: '200e9' in the checkpoint, "
                  "'100e9' here"},
                 "--set materials.steel.youngs_modulus=100e9");
}

TEST_CASE("a dt mismatch prints both time steps, not 0.000000", "[checkpoint]") {
  const Fixture f = make_checkpoint("ckpt-dt");
  // The same physics with another safety factor: another dt, the same fingerprint.
  const CommandResult r =
      expect_refused(f, f.checkpoint,
                     {"written with dt = ", "e-07 s, this case gives ", "must keep the time step"},
                     "--set time.safety=0.5");
  CHECK(r.output.find("0.000000") == std::string::npos);
}

TEST_CASE("a checkpoint of format 3 (one hash over the arrays in sequence) is still restored",
          "[checkpoint]") {
  const Fixture f = make_checkpoint("ckpt-format3");
  const auto old = copy_of(f, "format3.h5");
  make_format_3(old);
  const CommandResult r = run_ckpd("run " + f.file + " --quiet --set time.steps=15 --out " +
                                   (f.dir / "b").string() + " --restart " + old.string());
  INFO(r.output);
  CHECK(r.exit_code == 0);
  // The same file with one displacement changed is refused: the format-3 hash is checked.
  poke(old, "/body_0/displacement", H5T_NATIVE_DOUBLE, 4, 1e-9);
  expect_refused(f, old, {old.string(), "content hash"});
}
