#pragma once
// Without MPI in the build, ckpd runs as one process (OpenMP threads). Started by mpirun or srun
// as several processes, each would run the same case into the same output directory, every file
// written N times at once. The launchers say so in the environment; `run` and `sweep` refuse
// with exit 2. A build with MPI (CKPD_MPI) lets `run` through: the processes are the ranks of
// one run (src/engine/force_sharing.hpp).
#include <optional>
#include <string>

namespace ckpd {

// The refusal message when the environment says this process is one of several launched
// together (OMPI_COMM_WORLD_SIZE: Open MPI; PMI_SIZE: MPICH, Intel MPI; SLURM_STEP_NUM_TASKS:
// srun), or nothing when it is alone (a size of 1, or none of them set) or when
// CKPD_ALLOW_MULTIPLE=1 says the copies are independent runs (distinct --out directories).
// `sweep --shard` is not refused: each process may be given its own shard. `mpi_run`: the
// caller runs as one rank of an MPI run (`run` in a build with MPI): never refused.
std::optional<std::string> parallel_launch_refusal(bool mpi_run = false);

}  // namespace ckpd
