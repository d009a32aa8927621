#include "src/engine/ranks.hpp"

#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>

#ifdef CKPD_WITH_MPI
#include <mpi.h>
#endif

namespace ckpd::ranks {

namespace {

#ifdef CKPD_WITH_MPI
// Whether a launcher started this process as one of several (the variables launch_guard.cpp
// reads, and PMIx's).
bool launched_as_several() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"}) {
    const char* value = std::getenv(name);
    if (value != nullptr && std::atoll(value) > 1) return true;
  }
  return false;
}

bool active() {
  int initialised = 0, finalised = 0;
  MPI_Initialized(&initialised);
  MPI_Finalized(&finalised);
  return initialised != 0 && finalised == 0;
}
#endif

}  // namespace

bool built_with_mpi() {
#ifdef CKPD_WITH_MPI
  return true;
#else
  return false;
#endif
}

std::string mpi_text() {
#ifdef CKPD_WITH_MPI
  char text[MPI_MAX_LIBRARY_VERSION_STRING];
  int length = 0;
  MPI_Get_library_version(text, &length);
  std::string line(text, static_cast<std::size_t>(length));
  if (const std::size_t cut = line.find_first_of(",\n"); cut != std::string::npos) line.resize(cut);
  return line;
#else
  return "none";
#endif
}

Session::Session([[maybe_unused]] int* argc, [[maybe_unused]] char*** argv) {
#ifdef CKPD_WITH_MPI
  if (!launched_as_several() || active()) return;
  // Only the main thread calls MPI (between the OpenMP regions).
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
#endif
}

Session::~Session() {
#ifdef CKPD_WITH_MPI
  if (active()) MPI_Finalize();
#endif
}

int rank() {
#ifdef CKPD_WITH_MPI
  if (active()) {
    int r = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &r);
    return r;
  }
#endif
  return 0;
}

int count() {
#ifdef CKPD_WITH_MPI
  if (active()) {
    int n = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &n);
    return n;
  }
#endif
  return 1;
}

void sum_in_rank_order([[maybe_unused]] std::vector<double>& data,
                       [[maybe_unused]] std::vector<double>& gathered) {
#ifdef CKPD_WITH_MPI
  const int n = count();
  if (n == 1) return;
  const std::size_t m = data.size();
  all_gather(data, gathered);
  const std::size_t ranks = static_cast<std::size_t>(n);
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < m; ++k) {
    double s = gathered[k];
    for (std::size_t r = 1; r < ranks; ++r) s += gathered[r * m + k];
    data[k] = s;
  }
#endif
}

void all_gather(const std::vector<double>& data, std::vector<double>& gathered) {
#ifdef CKPD_WITH_MPI
  if (count() > 1) {
    const int m = static_cast<int>(data.size());
    gathered.resize(data.size() * static_cast<std::size_t>(count()));
    MPI_Allgather(data.data(), m, MPI_DOUBLE, gathered.data(), m, MPI_DOUBLE, MPI_COMM_WORLD);
    return;
  }
#endif
  gathered = data;
}

void gather_to_root(const std::vector<unsigned char>& data, std::vector<unsigned char>& gathered) {
#ifdef CKPD_WITH_MPI
  if (count() > 1) {
    const int n = count();
    const int mine = static_cast<int>(data.size());
    std::vector<int> sizes(root() ? static_cast<std::size_t>(n) : 0), at;
    MPI_Gather(&mine, 1, MPI_INT, sizes.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
    gathered.clear();
    if (root()) {
      at.assign(sizes.size(), 0);
      long long total = 0;
      for (std::size_t r = 0; r < sizes.size(); ++r) {
        at[r] = static_cast<int>(total);
        total += sizes[r];
      }
      if (total > std::numeric_limits<int>::max())
        throw std::runtime_error("gather to rank 0: more than 2 GB in one gather");
      gathered.resize(static_cast<std::size_t>(total));
    }
    MPI_Gatherv(data.data(), mine, MPI_BYTE, gathered.data(), sizes.data(), at.data(), MPI_BYTE, 0,
                MPI_COMM_WORLD);
    return;
  }
#endif
  gathered = data;
}

void exchange([[maybe_unused]] const std::vector<std::vector<double>>& send,
              [[maybe_unused]] std::vector<std::vector<double>>& receive) {
#ifdef CKPD_WITH_MPI
  const int n = count();
  if (n == 1) return;
  const int me = rank();
  constexpr int kHaloTag = 14;
  // Kept between calls (only the main thread calls MPI): a step allocates nothing once the
  // first exchange has sized it.
  static std::vector<MPI_Request> requests;
  requests.clear();
  for (int q = 0; q < n; ++q) {
    const std::size_t Q = static_cast<std::size_t>(q);
    if (q == me || Q >= receive.size() || receive[Q].empty()) continue;
    requests.emplace_back();
    MPI_Irecv(receive[Q].data(), static_cast<int>(receive[Q].size()), MPI_DOUBLE, q, kHaloTag,
              MPI_COMM_WORLD, &requests.back());
  }
  for (int q = 0; q < n; ++q) {
    const std::size_t Q = static_cast<std::size_t>(q);
    if (q == me || Q >= send.size() || send[Q].empty()) continue;
    requests.emplace_back();
    // MPI 3 takes a const buffer.
    MPI_Isend(send[Q].data(), static_cast<int>(send[Q].size()), MPI_DOUBLE, q, kHaloTag,
              MPI_COMM_WORLD, &requests.back());
  }
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
#endif
}

#ifdef CKPD_WITH_MPI
namespace {

// Exits the process (printing `message`) unless destroyed within kAgreeSeconds.
class Watchdog {
 public:
  Watchdog(int status, std::string message)
      : thread_([this, status, message = std::move(message)] {
          std::unique_lock<std::mutex> lock(mutex_);
          if (done_.wait_for(lock, std::chrono::seconds(kAgreeSeconds), [this] { return over_; }))
            return;
          std::cerr << "ckpd: error: rank " << rank() << ": " << message
                    << " (the other ranks did not stop with it: ending the job)" << std::endl;
          std::_Exit(status);  // mpirun ends the other ranks of a job that lost one
        }) {}
  ~Watchdog() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      over_ = true;
    }
    done_.notify_one();
    thread_.join();
  }
  Watchdog(const Watchdog&) = delete;
  Watchdog& operator=(const Watchdog&) = delete;

 private:
  std::mutex mutex_;
  std::condition_variable done_;
  bool over_ = false;
  std::thread thread_;  // last: it starts once the members above exist
};

}  // namespace
#endif

bool any(bool flag) {
#ifdef CKPD_WITH_MPI
  if (count() > 1) {
    int mine = flag ? 1 : 0, all = 0;
    MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    return all != 0;
  }
#endif
  return flag;
}

bool from_root(bool flag) {
#ifdef CKPD_WITH_MPI
  if (count() > 1) {
    int value = flag ? 1 : 0;
    MPI_Bcast(&value, 1, MPI_INT, 0, MPI_COMM_WORLD);
    return value != 0;
  }
#endif
  return flag;
}

long long from_root(long long value) {
#ifdef CKPD_WITH_MPI
  if (count() > 1) MPI_Bcast(&value, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
#endif
  return value;
}

std::uint64_t sum_wrapping(std::uint64_t value) {
#ifdef CKPD_WITH_MPI
  if (count() > 1) {
    std::uint64_t sum = 0;
    MPI_Allreduce(&value, &sum, 1, MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD);
    return sum;
  }
#endif
  return value;
}

int agree_on_failure(int status, [[maybe_unused]] const std::string& message) {
#ifdef CKPD_WITH_MPI
  if (count() > 1) {
    // A rank that failed where the others did not may wait here while they wait in a collective
    // it skipped: after kAgreeSeconds it prints its message and exits, and mpirun ends the job.
    const std::optional<Watchdog> watchdog =
        status != 0 ? std::optional<Watchdog>(std::in_place, status, message) : std::nullopt;
    int worst = 0;
    MPI_Allreduce(&status, &worst, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    if (worst == 0) return 0;
    const int mine = status != 0 ? rank() : count();
    int first = 0;
    MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (rank() == first) std::cerr << "ckpd: error: " << message << std::endl;
    return worst;
  }
#endif
  return status;
}

void abort_all([[maybe_unused]] int status) {
#ifdef CKPD_WITH_MPI
  if (count() > 1) MPI_Abort(MPI_COMM_WORLD, status);
#endif
}

}  // namespace ckpd::ranks
