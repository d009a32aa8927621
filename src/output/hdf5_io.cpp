#include "src/output/hdf5_io.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <mutex>
#include <stdexcept>
#include <thread>

#ifdef CKPD_PARALLEL_HDF5
#include <mpi.h>
#endif

#include "src/engine/ranks.hpp"
#include "src/output/content_hash.hpp"

namespace ckpd::hdf5 {

namespace {

// HDF5 closes what is still open when the process exits, unless told not to before its first
// call: a file whose close failed stays in its tables, already freed, and a second close there
// crashes the process after the failure was reported.
const bool kNoCloseAtExit = H5dont_atexit() >= 0;

thread_local bool shared_write = false;  // inside a SharedWrite
std::string shared_path;                 // the file the ranks write together now

// What the system said about the last failed call, when it set errno (a full disk: "No space
// left on device").
std::string system_reason(int error) {
  return error != 0 ? std::string(" (") + std::strerror(error) + ")" : std::string();
}

}  // namespace

void fail(const std::string& message) {
  if (shared_write) {
    // The other ranks are in, or on their way to, a collective call this rank will not make.
    std::cerr << "ckpd: error: rank " << ranks::rank() << ": " << message
              << "; ending every rank (a file the ranks write together cannot be finished)"
              << std::endl;
    ranks::abort_all(1);
  }
  throw std::runtime_error(message);
}

struct SharedWrite::Watchdog {
  std::mutex mutex;
  std::condition_variable finished;
  bool done = false;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  std::thread thread;
};

namespace {

double longest_shared_write = 0;  // seconds, this process's longest so far

double shared_write_limit() {
  double limit = 300;
  if (const char* v = std::getenv("CKPD_SHARED_WRITE_TIMEOUT"); v && std::atof(v) > 0)
    limit = std::atof(v);
  return std::max(limit, 20 * longest_shared_write);
}

}  // namespace

SharedWrite::SharedWrite(bool shared) : previous_(shared_write) {
  shared_write = shared_write || shared;
  if (!shared || previous_) return;
  watchdog_ = std::make_unique<Watchdog>();
  Watchdog& w = *watchdog_;
  const double limit = shared_write_limit();
  w.thread = std::thread([&w, limit] {
    std::unique_lock<std::mutex> lock(w.mutex);
    if (w.finished.wait_for(lock, std::chrono::duration<double>(limit), [&w] { return w.done; }))
      return;
    std::cerr << "ckpd: error: rank " << ranks::rank() << ": a file the ranks write together ("
              << shared_path << ") is not finished after " << limit
              << " s: a write failed inside parallel HDF5 (a full disk?) and the ranks wait in "
                 "different collectives; ending every rank (CKPD_SHARED_WRITE_TIMEOUT sets the "
                 "time allowed)"
              << std::endl;
    ranks::abort_all(1);
  });
}

SharedWrite::~SharedWrite() {
  shared_write = previous_;
  if (!watchdog_) return;
  {
    const std::lock_guard<std::mutex> lock(watchdog_->mutex);
    watchdog_->done = true;
  }
  watchdog_->finished.notify_one();
  watchdog_->thread.join();
  longest_shared_write = std::max(
      longest_shared_write,
      std::chrono::duration<double>(std::chrono::steady_clock::now() - watchdog_->start).count());
}

Handle::Handle(hid_t id, herr_t (*close)(hid_t), const std::string& what)
    : id_(id), close_(close), what_(what) {
  if (id_ < 0) fail("HDF5: cannot " + what + system_reason(errno));
}

void Handle::close() {
  const hid_t id = id_;
  id_ = -1;
  errno = 0;
  // HDF5 writes a dataset's or file's cached data at its close: a failure there is a failed write.
  const std::string object = what_.rfind("create ", 0) == 0 ? what_.substr(7) : what_;
  if (close_(id) < 0) fail("HDF5: cannot write " + object + system_reason(errno));
}

void flush_file(hid_t file, const std::string& path) {
  errno = 0;
  if (H5Fflush(file, H5F_SCOPE_GLOBAL) < 0)
    fail("HDF5: cannot write " + path + system_reason(errno));
}

void silence_errors() {
  (void)kNoCloseAtExit;
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
                 const void* data, const RowShare& share, std::size_t columns, RowsHash* hash) {
  const std::size_t row_bytes = columns * H5Tget_size(memory_type);
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
    errno = 0;
    if (share.rows > 0 && H5Dwrite(set, memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
      fail("HDF5: cannot write dataset " + name + system_reason(errno));
    if (hash) hash->add(set, data, share, row_bytes);
    set.close();
    return;
  }
  if (share.rows == 0) {  // an empty dataset: nothing to write, on any rank
    set.close();
    return;
  }
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
      fail("HDF5: cannot select the rows of " + name);
  }
  Handle transfer(H5Pcreate(H5P_DATASET_XFER), H5Pclose, "make a transfer list");
  H5Pset_dxpl_mpio(transfer, H5FD_MPIO_COLLECTIVE);
  errno = 0;
  if (H5Dwrite(set, memory_type, memory, space, transfer, data) < 0)
    fail("HDF5: cannot write dataset " + name + system_reason(errno));
  if (hash) hash->add(set, data, share, row_bytes);
  set.close();
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
  if (H5Awrite(attr, memory_type, &value) < 0) fail("HDF5: cannot write attribute " + name);
  attr.close();
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

#ifdef CKPD_PARALLEL_HDF5
namespace {

// A failed MPI-IO call in a shared file ends every rank at once: HDF5 does not always report it
// on every rank, and a rank it reports it to may leave a collective inside HDF5 (the file's close)
// that the others then wait in for ever.
void end_on_file_error(MPI_File*, int* code, ...) {
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(*code, text, &length);
  std::cerr << "ckpd: error: rank " << ranks::rank() << ": " << shared_path << ": cannot write ("
            << std::string(text, static_cast<std::size_t>(length))
            << "); ending every rank (a file the ranks write together cannot be finished)"
            << std::endl;
  MPI_Abort(MPI_COMM_WORLD, 1);
}

}  // namespace
#endif

hid_t create_shared_file(const std::string& path) {
#ifdef CKPD_PARALLEL_HDF5
  // Files MPI-IO opens from now on (HDF5's below) get the handler.
  static MPI_Errhandler handler = [] {
    MPI_Errhandler h;
    MPI_File_create_errhandler(end_on_file_error, &h);
    return h;
  }();
  MPI_File_set_errhandler(MPI_FILE_NULL, handler);
  shared_path = path;
  Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "make a file access list");
  if (H5Pset_fapl_mpio(access, MPI_COMM_WORLD, MPI_INFO_NULL) < 0)
    fail("HDF5: cannot use MPI-IO for " + path);
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

namespace {

std::string object_path(hid_t object) {
  const ssize_t size = H5Iget_name(object, nullptr, 0);
  if (size < 0) fail("HDF5: cannot read the path of a dataset");
  std::string path(static_cast<std::size_t>(size) + 1, '\0');
  H5Iget_name(object, path.data(), path.size());
  path.resize(static_cast<std::size_t>(size));
  return path;
}

std::uint64_t row_hash(const std::string& path, std::uint64_t row, const unsigned char* bytes,
                       std::size_t size) {
  ContentHash h;
  h.text(path);
  h.value(row);
  h.bytes(bytes, size);
  return h.value();
}

herr_t hash_object(hid_t group, const char* name, const H5L_info_t*, void* sum);

}  // namespace

void RowsHash::add(hid_t dataset, const void* data, const RowShare& share, std::size_t row_bytes) {
  const std::string path = object_path(dataset);
  const auto* p = static_cast<const unsigned char*>(data);
  for (const auto& [first, count] : share.runs)
    for (std::size_t k = 0; k < count; ++k, p += row_bytes)
      sum_ += row_hash(path, first + k, p, row_bytes);
}

namespace {

// One dataset's rows as stored, or a group's objects in turn (-1: unreadable).
herr_t hash_object(hid_t group, const char* name, const H5L_info_t*, void* sum) {
  try {
    Handle object(H5Oopen(group, name, H5P_DEFAULT), H5Oclose, std::string("open ") + name);
    if (H5Iget_type(object) == H5I_GROUP)
      return H5Literate(object, H5_INDEX_NAME, H5_ITER_INC, nullptr, hash_object, sum);
    if (H5Iget_type(object) != H5I_DATASET) return 0;
    Handle space(H5Dget_space(object), H5Sclose, "read a shape");
    Handle stored(H5Dget_type(object), H5Tclose, "read a type");
    Handle type(H5Tget_native_type(stored, H5T_DIR_ASCEND), H5Tclose, "read a type");
    hsize_t dims[2] = {0, 1};
    const int rank = H5Sget_simple_extent_ndims(space);
    if (rank < 1 || rank > 2 || H5Sget_simple_extent_dims(space, dims, nullptr) < 0) return -1;
    const std::size_t row_bytes = static_cast<std::size_t>(dims[1]) * H5Tget_size(type);
    std::vector<unsigned char> bytes(static_cast<std::size_t>(dims[0]) * row_bytes);
    if (!bytes.empty() && H5Dread(object, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, bytes.data()) < 0)
      return -1;
    const std::string path = object_path(object);
    for (std::size_t r = 0; r < dims[0]; ++r)
      *static_cast<std::uint64_t*>(sum) +=
          row_hash(path, r, bytes.data() + r * row_bytes, row_bytes);
    return 0;
  } catch (const std::exception&) {
    return -1;
  }
}

}  // namespace

std::uint64_t file_rows_hash(hid_t file) {
  std::uint64_t sum = 0;
  if (H5Literate(file, H5_INDEX_NAME, H5_ITER_INC, nullptr, hash_object, &sum) < 0)
    throw std::runtime_error("HDF5: cannot read every dataset back");
  return sum;
}

void write_doubles(hid_t group, const std::string& name, const double* data, std::size_t rows,
                   std::size_t columns) {
  write_doubles(group, name, data, RowShare::all(rows), columns);
}

void write_doubles(hid_t group, const std::string& name, const double* data, const RowShare& share,
                   std::size_t columns, RowsHash* hash) {
  write_array(group, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, data, share, columns, hash);
}

void write_vectors(hid_t group, const std::string& name, const std::vector<Vec3>& data) {
  write_vectors(group, name, data, RowShare::all(data.size()));
}

void write_vectors(hid_t group, const std::string& name, const std::vector<Vec3>& data,
                   const RowShare& share, RowsHash* hash) {
  // Eigen's Vector3d is three contiguous doubles.
  static_assert(sizeof(Vec3) == 3 * sizeof(double));
  write_doubles(group, name, data.empty() ? nullptr : data[0].data(), share, 3, hash);
}

void write_int32(hid_t group, const std::string& name, const std::vector<std::int32_t>& data,
                 std::size_t columns) {
  write_int32(group, name, data, RowShare::all(data.size() / columns), columns);
}

void write_int32(hid_t group, const std::string& name, const std::vector<std::int32_t>& data,
                 const RowShare& share, std::size_t columns, RowsHash* hash) {
  write_array(group, name, H5T_STD_I32LE, H5T_NATIVE_INT32, data.data(), share, columns, hash);
}

void write_bytes(hid_t group, const std::string& name, const std::vector<std::uint8_t>& data) {
  write_bytes(group, name, data, RowShare::all(data.size()));
}

void write_bytes(hid_t group, const std::string& name, const std::vector<std::uint8_t>& data,
                 const RowShare& share, RowsHash* hash) {
  write_array(group, name, H5T_STD_U8LE, H5T_NATIVE_UINT8, data.data(), share, 1, hash);
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
  if (H5Awrite(attr, type, value.c_str()) < 0) fail("HDF5: cannot write attribute " + name);
  attr.close();
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
