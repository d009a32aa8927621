#include "src/cli/launch_guard.hpp"

#include <cstdlib>

namespace ckpd {

std::optional<std::string> parallel_launch_refusal(bool mpi_run) {
  if (mpi_run) return std::nullopt;
  if (const char* allow = std::getenv("CKPD_ALLOW_MULTIPLE"); allow != nullptr && *allow == '1')
    return std::nullopt;
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "SLURM_STEP_NUM_TASKS"}) {
    const char* value = std::getenv(name);
    if (value == nullptr) continue;
    char* end = nullptr;
    const long long size = std::strtoll(value, &end, 10);
    if (end == value || *end != '\0' || size <= 1) continue;
    return "this process is one of " + std::string(value) + " started together (" + name + "=" +
           value +
           "), but ckpd runs as one process with threads (--threads N): the copies would all "
           "run the same case into the same files. Start it without mpirun or srun; for a "
           "sweep over several processes or nodes use `ckpd sweep --shard K/N` (README, "
           "\"Sweeps\"); for independent runs with distinct --out directories set "
           "CKPD_ALLOW_MULTIPLE=1. One case over several processes is `mpirun -np N ckpd run` "
           "in a build with MPI (cmake -DCKPD_MPI=ON, packages libopenmpi-dev and openmpi-bin; "
           "docs/SCALING.md)";
  }
  return std::nullopt;
}

}  // namespace ckpd
