#include "src/output/hdf5_io.hpp"

#include <stdexcept>

#ifdef CKPD_PARALLEL_HDF5
#include <mpi.h>
#endif

namespace ckpd::hdf5 {

Handle::Handle(hid_t id, herr_t (*close)(hid_t), const std::string& what) : id_(id), close_(close) {
  if (id_ < 0) throw std::runtime_error("HDF5: cannot " + what);
}

void silence_errors() {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

namespace {

// Whether `object` lives in a file opened with MPI-IO (create_shared_file).
bool in_shared_file(hid_t object) {
#ifdef CKPD_PARALLEL_HDF5
  Handle file(H5Iget_file_id(object), H5Fclose, "find the file of a group");
  Handle access(H5Fget_access_plist(file), H5Pclose, "read a file's access list");
  return H5Pget_driver(access) == H5FD_MPIO;
#else
  (void)object;
  return false;
#endif
}

void write_array(hid_t group, const std::string& name, hid_t file_type, hid_t memory_type,
                 const void* data, const RowShare& share, std::size_t columns) {
  const hsize_t dims[2] = {share.rows, columns};
  const int rank = columns == 1 ? 1 : 2;
  Handle space(H5Screate_simple(rank, dims, nullptr), H5Sclose, "make a dataspace for " + name);
  const bool shared = in_shared_file(group);
  // A shared file: no fill values written first (every row is written by some rank).
  Handle creation(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, "make a dataset creation list");
  if (shared) H5Pset_fill_time(creation, H5D_FILL_TIME_NEVER);
  Handle set(H5Dcreate2(group, name.c_str(), file_type, space, H5P_DEFAULT, creation, H5P_DEFAULT),
             H5Dclose, "create dataset " + name);
  if (!shared) {
    if (share.mine() != share.rows)
      throw std::logic_error("HDF5: dataset " + name + ": part of its rows outside a shared file");
    if (share.rows > 0 && H5Dwrite(set, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
      throw std::runtime_error("HDF5: cannot write dataset " + name);
    return;
  }
  if (share.rows == 0) return;  // an empty dataset: nothing to write, on any rank
#ifdef CKPD_PARALLEL_HDF5
  // This rank's runs of rows in the file, its rows one after the other in memory; every rank
  // takes part in the collective write, one with no rows with empty selections.
  const hsize_t mine[2] = {share.mine(), columns};
  Handle memory(H5Screate_simple(rank, mine, nullptr), H5Sclose, "make a dataspace for " + name);
  if (share.runs.empty()) {
    H5Sselect_none(space);
    H5Sselect_none(memory);
  }
  for (std::size_t k = 0; k < share.runs.size(); ++k) {
    const hsize_t start[2] = {share.runs[k].first, 0};
    const hsize_t count[2] = {share.runs[k].second, columns};
    if (H5Sselect_hyperslab(space, k == 0 ? H5S_SELECT_SET : H5S_SELECT_OR, start, nullptr, count,
                            nullptr) < 0)
      throw std::runtime_error("HDF5: cannot select the rows of " + name);
  }
  Handle transfer(H5Pcreate(H5P_DATASET_XFER), H5Pclose, "make a transfer list");
  H5Pset_dxpl_mpio(transfer, H5FD_MPIO_COLLECTIVE);
  if (H5Dwrite(set, memory_type, memory, space, transfer, data) < 0)
    throw std::runtime_error("HDF5: cannot write dataset " + name);
#else
  (void)memory_type;
  (void)data;
#endif
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

bool shared_files() {
#ifdef CKPD_PARALLEL_HDF5
  return true;
#else
  return false;
#endif
}

hid_t create_shared_file(const std::string& path) {
#ifdef CKPD_PARALLEL_HDF5
  Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "make a file access list");
  if (H5Pset_fapl_mpio(access, MPI_COMM_WORLD, MPI_INFO_NULL) < 0)
    throw std::runtime_error("HDF5: cannot use MPI-IO for " + path);
  return H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access);
#else
  throw std::logic_error("HDF5: " + path + ": this build has no parallel HDF5");
#endif
}

RowShare RowShare::all(std::size_t rows) {
  RowShare share = none(rows);
  share.add(0, rows);
  return share;
}

void RowShare::add(std::size_t first, std::size_t count) {
  if (count == 0) return;
  if (!runs.empty() && runs.back().first + runs.back().second == first)
    runs.back().second += count;
  else
    runs.emplace_back(first, count);
}

std::size_t RowShare::mine() const {
  std::size_t n = 0;
  for (const auto& run : runs) n += run.second;
  return n;
}

void write_doubles(hid_t group, const std::string& name, const double* data, std::size_t rows,
                   std::size_t columns) {
  write_doubles(group, name, data, RowShare::all(rows), columns);
}

void write_doubles(hid_t group, const std::string& name, const double* data, const RowShare& share,
                   std::size_t columns) {
  write_array(group, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, data, share, columns);
}

void write_vectors(hid_t group, const std::string& name, const std::vector<Vec3>& data) {
  write_vectors(group, name, data, RowShare::all(data.size()));
}

void write_vectors(hid_t group, const std::string& name, const std::vector<Vec3>& data,
                   const RowShare& share) {
  // Eigen's Vector3d is three contiguous doubles.
  static_assert(sizeof(Vec3) == 3 * sizeof(double));
  write_doubles(group, name, data.empty() ? nullptr : data[0].data(), share, 3);
}

void write_int32(hid_t group, const std::string& name, const std::vector<std::int32_t>& data,
                 std::size_t columns) {
  write_int32(group, name, data, RowShare::all(data.size() / columns), columns);
}

void write_int32(hid_t group, const std::string& name, const std::vector<std::int32_t>& data,
                 const RowShare& share, std::size_t columns) {
  write_array(group, name, H5T_STD_I32LE, H5T_NATIVE_INT32, data.data(), share, columns);
}

void write_bytes(hid_t group, const std::string& name, const std::vector<std::uint8_t>& data) {
  write_bytes(group, name, data, RowShare::all(data.size()));
}

void write_bytes(hid_t group, const std::string& name, const std::vector<std::uint8_t>& data,
                 const RowShare& share) {
  write_array(group, name, H5T_STD_U8LE, H5T_NATIVE_UINT8, data.data(), share, 1);
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
