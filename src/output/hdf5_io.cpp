#include "src/output/hdf5_io.hpp"

#include <stdexcept>

namespace ckpd::hdf5 {

Handle::Handle(hid_t id, herr_t (*close)(hid_t), const std::string& what) : id_(id), close_(close) {
  if (id_ < 0) throw std::runtime_error("HDF5: cannot " + what);
}

void silence_errors() {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

namespace {

void write_array(hid_t group, const std::string& name, hid_t file_type, hid_t memory_type,
                 const void* data, std::size_t rows, std::size_t columns) {
  const hsize_t dims[2] = {rows, columns};
  Handle space(H5Screate_simple(columns == 1 ? 1 : 2, dims, nullptr), H5Sclose,
               "make a dataspace for " + name);
  Handle set(
      H5Dcreate2(group, name.c_str(), file_type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
      H5Dclose, "create dataset " + name);
  if (rows > 0 && H5Dwrite(set, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    throw std::runtime_error("HDF5: cannot write dataset " + name);
}

void read_array(hid_t group, const std::string& name, hid_t memory_type, void* data,
                std::size_t expected) {
  Handle set(H5Dopen2(group, name.c_str(), H5P_DEFAULT), H5Dclose, "open dataset " + name);
  Handle space(H5Dget_space(set), H5Sclose, "read the shape of " + name);
  const hssize_t count = H5Sget_simple_extent_npoints(space);
  if (count < 0 || static_cast<std::size_t>(count) != expected)
    throw std::runtime_error("HDF5: dataset " + name + " holds " + std::to_string(count) +
                             " values, expected " + std::to_string(expected));
  if (expected > 0 && H5Dread(set, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    throw std::runtime_error("HDF5: cannot read dataset " + name);
}

template <class T>
void write_scalar_attribute(hid_t object, const std::string& name, hid_t file_type,
                            hid_t memory_type, const T& value) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose, "make a dataspace");
  Handle attr(H5Acreate2(object, name.c_str(), file_type, space, H5P_DEFAULT, H5P_DEFAULT),
              H5Aclose, "create attribute " + name);
  if (H5Awrite(attr, memory_type, &value) < 0)
    throw std::runtime_error("HDF5: cannot write attribute " + name);
}

template <class T>
T read_scalar_attribute(hid_t object, const std::string& name, hid_t memory_type) {
  Handle attr(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose, "open attribute " + name);
  T value{};
  if (H5Aread(attr, memory_type, &value) < 0)
    throw std::runtime_error("HDF5: cannot read attribute " + name);
  return value;
}

}  // namespace

void write_doubles(hid_t group, const std::string& name, const double* data, std::size_t rows,
                   std::size_t columns) {
  write_array(group, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, data, rows, columns);
}

void write_vectors(hid_t group, const std::string& name, const std::vector<Vec3>& data) {
  // Eigen's Vector3d is three contiguous doubles.
  static_assert(sizeof(Vec3) == 3 * sizeof(double));
  write_doubles(group, name, data.empty() ? nullptr : data[0].data(), data.size(), 3);
}

void write_int32(hid_t group, const std::string& name, const std::vector<std::int32_t>& data,
                 std::size_t columns) {
  write_array(group, name, H5T_STD_I32LE, H5T_NATIVE_INT32, data.data(), data.size() / columns,
              columns);
}

void write_bytes(hid_t group, const std::string& name, const std::vector<std::uint8_t>& data) {
  write_array(group, name, H5T_STD_U8LE, H5T_NATIVE_UINT8, data.data(), data.size(), 1);
}

void write_double_attribute(hid_t object, const std::string& name, double value) {
  write_scalar_attribute(object, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, value);
}

void write_int64_attribute(hid_t object, const std::string& name, long long value) {
  write_scalar_attribute(object, name, H5T_STD_I64LE, H5T_NATIVE_LLONG, value);
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

std::vector<double> read_doubles(hid_t group, const std::string& name, std::size_t expected) {
  std::vector<double> out(expected);
  read_array(group, name, H5T_NATIVE_DOUBLE, out.data(), expected);
  return out;
}

std::vector<Vec3> read_vectors(hid_t group, const std::string& name, std::size_t expected) {
  std::vector<Vec3> out(expected);
  read_array(group, name, H5T_NATIVE_DOUBLE, expected ? out[0].data() : nullptr, 3 * expected);
  return out;
}

std::vector<std::uint8_t> read_bytes(hid_t group, const std::string& name, std::size_t expected) {
  std::vector<std::uint8_t> out(expected);
  read_array(group, name, H5T_NATIVE_UINT8, out.data(), expected);
  return out;
}

double read_double_attribute(hid_t object, const std::string& name) {
  return read_scalar_attribute<double>(object, name, H5T_NATIVE_DOUBLE);
}

long long read_int64_attribute(hid_t object, const std::string& name) {
  return read_scalar_attribute<long long>(object, name, H5T_NATIVE_LLONG);
}

std::string read_string_attribute(hid_t object, const std::string& name) {
  Handle attr(H5Aopen(object, name.c_str(), H5P_DEFAULT), H5Aclose, "open attribute " + name);
  Handle type(H5Aget_type(attr), H5Tclose, "read the type of " + name);
  const std::size_t size = H5Tget_size(type);
  std::string value(size, '\0');
  Handle memory(H5Tcopy(H5T_C_S1), H5Tclose, "copy a string type");
  H5Tset_size(memory, size);
  if (H5Aread(attr, memory, value.data()) < 0)
    throw std::runtime_error("HDF5: cannot read attribute " + name);
  while (!value.empty() && value.back() == '\0') value.pop_back();
  return value;
}

}  // namespace ckpd::hdf5
