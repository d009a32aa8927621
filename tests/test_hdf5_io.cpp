// The HDF5 helpers (src/output/hdf5_io.hpp) under field frames and checkpoints: what is written
// reads back bit for bit, and a wrong size or a missing dataset is an error, not a silent read.
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>
#include <vector>

#include "src/output/hdf5_io.hpp"

namespace h = ckpd::hdf5;

TEST_CASE("datasets and attributes round-trip bit for bit", "[hdf5_io]") {
  h::silence_errors();
  const std::string path =
      (std::filesystem::temp_directory_path() / "ckpd_test_hdf5_io.h5").string();
  const std::vector<double> d = {0.1, -2.5e-300, 1e300, 3.0, 0.0, -0.0};
  const std::vector<ckpd::Vec3> v = {{1, 2, 3}, {-4e-9, 5.5, 6e12}};
  const std::vector<std::uint8_t> bytes = {0, 1, 1, 0, 255};
  {
    h::Handle file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose,
                   "create");
    h::write_doubles(file, "d", d.data(), 3, 2);
    h::write_vectors(file, "v", v);
    h::write_bytes(file, "b", bytes);
    h::write_double_attribute(file, "x", 1.0 / 3.0);
    h::write_int64_attribute(file, "n", -9007199254740993LL);
    h::write_string_attribute(file, "s", "ckpd checkpoint");
  }
  h::Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "open");
  CHECK(h::read_doubles(file, "d", 6) == d);
  const std::vector<ckpd::Vec3> back = h::read_vectors(file, "v", 2);
  CHECK(back[0] == v[0]);
  CHECK(back[1] == v[1]);
  CHECK(h::read_bytes(file, "b", 5) == bytes);
  CHECK(h::read_double_attribute(file, "x") == 1.0 / 3.0);
  CHECK(h::read_int64_attribute(file, "n") == -9007199254740993LL);
  CHECK(h::read_string_attribute(file, "s") == "ckpd checkpoint");
  // A size other than the stored one, or a name that is not there, throws.
  CHECK_THROWS_AS(h::read_doubles(file, "d", 5), std::runtime_error);
  CHECK_THROWS_AS(h::read_vectors(file, "missing", 2), std::runtime_error);
  CHECK_THROWS_AS(h::read_string_attribute(file, "missing"), std::runtime_error);
  std::filesystem::remove(path);
}
