#pragma once
// The MPI ranks of a run (issue 14: distributed force work over replicated state). Every rank
// holds the whole scene and integrates it identically; only the internal-force work is split
// (force_sharing.hpp). Without MPI in the build (CMake option CKPD_MPI), or in a process not
// started by a launcher as one of several, there is one rank and every call here is a no-op, so
// ckpd runs exactly as before.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ckpd::ranks {

// Whether this build has MPI (CKPD_MPI), and in words for `ckpd --version` and summary.json:
// the library's own first line ("Open MPI v4.1.4, ...") or "none".
bool built_with_mpi();
std::string mpi_text();

// Initialises MPI when the build has it and the environment says this process is one of
// several started together (OMPI_COMM_WORLD_SIZE, PMI_SIZE, PMIX_RANK with a size above 1);
// finalises it on destruction. One per process, in `ckpd run` only.
class Session {
 public:
  Session(int* argc, char*** argv);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
};

int rank();   // 0 without MPI
int count();  // 1 without MPI
inline bool root() {
  return rank() == 0;
}

// data <- the sum over ranks of every rank's data (the same length on all), added in rank order
// 0, 1, ..., R-1 for every entry, so that the result is the same bit for bit on every rank and
// for every run at this rank count (MPI_Allreduce's order is not guaranteed). `gathered` is
// scratch (R x data.size()), kept by the caller so that a step allocates nothing.
void sum_in_rank_order(std::vector<double>& data, std::vector<double>& gathered);

// gathered <- every rank's data (the same length on all), rank after rank, on every rank. Without
// MPI (or with one rank) a copy of data.
void all_gather(const std::vector<double>& data, std::vector<double>& gathered);

// On rank 0, gathered <- every rank's bytes (any length per rank), rank after rank; on the other
// ranks gathered is left empty. Without MPI a copy of data. A collective.
void gather_to_root(const std::vector<unsigned char>& data, std::vector<unsigned char>& gathered);

// Point-to-point exchange (the halo's messages, halo_exchange.hpp): send[q] goes to rank q and
// receive[q] is filled from rank q, for every q != this rank whose buffer is not empty; both
// sides must agree on the sizes (the halo lists make them). Non-blocking sends and receives, all
// posted before any wait. A collective over the ranks that exchange; without MPI a no-op.
void exchange(const std::vector<std::vector<double>>& send,
              std::vector<std::vector<double>>& receive);

// Whether `flag` is true on any rank (a collective: every rank calls it at the same point).
bool any(bool flag);
// Rank 0's value of `flag` (`value`) on every rank.
bool from_root(bool flag);
long long from_root(long long value);
// The sum over ranks of `value` modulo 2^64 (exact, the same in any order), on every rank.
std::uint64_t sum_wrapping(std::uint64_t value);

// A failure in a phase that every rank passes (set-up, output folder, checkpoint): every rank
// calls it with its exit status (0: none) and message. Returns the largest status over ranks;
// the lowest failing rank prints its message once on stderr ("ckpd: error: ..."). With one rank
// it only returns `status` (the caller prints as before). A failing rank whose call is not met
// by every rank within kAgreeSeconds (the others wait in a collective it skipped) prints its
// message and exits with `status`, and mpirun ends the job: a rank's failure never hangs it.
inline constexpr int kAgreeSeconds = 5;
int agree_on_failure(int status, const std::string& message);

// Stops every rank at once after an error that only some ranks may have seen (a write failing
// on rank 0 during the run): MPI_Abort with `status`; without MPI it returns.
void abort_all(int status);

}  // namespace ckpd::ranks
