#pragma once
// Small RAII and read/write helpers over the HDF5 C API, shared by field frames and
// checkpoints. Every failure throws std::runtime_error naming what could not be done; while a
// file the ranks share is written (SharedWrite), it ends every rank instead (a rank that threw
// would wait for ever in the collective close its handles make while the stack unwinds).
#include <hdf5.h>

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "bodies/vec.hpp"

namespace ckpd::hdf5 {

// Closes an HDF5 handle when it goes out of scope; a negative id is an error. A writer calls
// close() itself: HDF5 writes its cached data there, so a close that fails is a write that
// failed. A handle whose close failed is never closed again (HDF5 may already have freed it).
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t), const std::string& what);
  ~Handle() {
    if (id_ >= 0) close_(id_);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  operator hid_t() const { return id_; }
  // Closes now; throws (names `what_`) when HDF5 reports a failure.
  void close();

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
  std::string what_;
};

// Writes what HDF5 cached of an open file (a collective in a shared file) and throws, or ends
// every rank, when that fails. Writers call it before the file's close: a rank whose close fails
// to write goes on into the close's next collective, which the other ranks never join, while a
// failed flush returns to the caller.
void flush_file(hid_t file, const std::string& path);

// HDF5's own error printing off: errors come back as exceptions. Also keeps HDF5 from closing
// at exit what is still open (a file whose close failed would be closed a second time there).
void silence_errors();

// A failed write: throws std::runtime_error(message), or inside a SharedWrite prints the message
// and ends every rank (MPI_Abort, exit status 1).
[[noreturn]] void fail(const std::string& message);

// While one lives, this process writes a file together with the other ranks: fail() ends the job.
// A watchdog ends it too when the write has not finished in time: parallel HDF5 may report a
// failed write (a full disk) on one rank only, inside a flush or close, and that rank then waits
// in a different collective from the others', for ever. The time allowed is
// CKPD_SHARED_WRITE_TIMEOUT seconds (default 300), or 20 times the longest shared write of the
// run so far where that is longer.
class SharedWrite {
 public:
  explicit SharedWrite(bool shared);
  ~SharedWrite();
  SharedWrite(const SharedWrite&) = delete;
  SharedWrite& operator=(const SharedWrite&) = delete;

 private:
  bool previous_;
  struct Watchdog;
  std::unique_ptr<Watchdog> watchdog_;
};

// A file the ranks of a distributed run write together (parallel HDF5 over MPI-IO): every rank
// makes the same calls in the same order (groups, attributes and datasets alike), each writing its
// own rows of the datasets (RowShare). Only in a build with parallel HDF5 (shared_files()); its
// handle closes with H5Fclose, a collective.
bool shared_files();
hid_t create_shared_file(const std::string& path);

// The rows (first dimension) of a dataset this process writes: all of them, or in a shared file
// its own runs of rows (first, count), increasing and disjoint; its data holds just those rows,
// one run after the other. The other processes write the rest in the same call.
struct RowShare {
  std::size_t rows = 0;  // the whole dataset's
  std::vector<std::pair<std::size_t, std::size_t>> runs;
  static RowShare all(std::size_t rows);
  static RowShare none(std::size_t rows) { return {rows, {}}; }
  // Appends rows [first, first + count), after the last run (merged with it when adjacent).
  void add(std::size_t first, std::size_t count);
  std::size_t mine() const;  // rows this process writes
};

// The sum (modulo 2^64) of a hash of every row written into a file: the dataset's path, the row's
// index and its bytes. Any split of the rows over ranks gives the same sum; a changed byte changes
// its row's hash and with it the sum. Reading a file back (file_rows_hash) gives the same sum.
class RowsHash {
 public:
  void add(hid_t dataset, const void* data, const RowShare& share, std::size_t row_bytes);
  std::uint64_t value() const { return sum_; }

 private:
  std::uint64_t sum_ = 0;
};
// The RowsHash of every dataset in every group of an open file.
std::uint64_t file_rows_hash(hid_t file);

void write_doubles(hid_t group, const std::string& name, const double* data, std::size_t rows,
                   std::size_t columns);
void write_doubles(hid_t group, const std::string& name, const double* data, const RowShare& share,
                   std::size_t columns, RowsHash* hash = nullptr);
void write_vectors(hid_t group, const std::string& name, const std::vector<Vec3>& data);
void write_vectors(hid_t group, const std::string& name, const std::vector<Vec3>& data,
                   const RowShare& share, RowsHash* hash = nullptr);
// `columns` > 1: a (data.size() / columns) x columns array.
void write_int32(hid_t group, const std::string& name, const std::vector<std::int32_t>& data,
                 std::size_t columns = 1);
void write_int32(hid_t group, const std::string& name, const std::vector<std::int32_t>& data,
                 const RowShare& share, std::size_t columns, RowsHash* hash = nullptr);
void write_bytes(hid_t group, const std::string& name, const std::vector<std::uint8_t>& data);
void write_bytes(hid_t group, const std::string& name, const std::vector<std::uint8_t>& data,
                 const RowShare& share, RowsHash* hash = nullptr);
void write_double_attribute(hid_t object, const std::string& name, double value);
void write_int64_attribute(hid_t object, const std::string& name, long long value);
void write_string_attribute(hid_t object, const std::string& name, const std::string& value);

// Readers check the stored size against `expected` elements (rows x columns).
std::vector<double> read_doubles(hid_t group, const std::string& name, std::size_t expected);
std::vector<Vec3> read_vectors(hid_t group, const std::string& name, std::size_t expected);
std::vector<std::uint8_t> read_bytes(hid_t group, const std::string& name, std::size_t expected);
double read_double_attribute(hid_t object, const std::string& name);
long long read_int64_attribute(hid_t object, const std::string& name);
std::string read_string_attribute(hid_t object, const std::string& name);

}  // namespace ckpd::hdf5
