#pragma once
// Checkpoints: the full state of a run in one HDF5 file, enough to continue it bit for bit:
// the run's counters, and per body displacement, velocity, acceleration, force densities,
// strain-energy density and the intact flag of every bond (a restart that restored only
// positions and velocities would heal the cracks). Written under a temporary name, every HDF5 call
// checked to the file's close, synced and renamed (durable_file.hpp), so a checkpoint on disk is
// always complete: a write that fails (a full disk) throws OutputError and leaves the previous
// checkpoint as it was.
#include <stdexcept>
#include <string>

#include "src/engine/simulation.hpp"

namespace ckpd {

// A checkpoint that cannot be used: unreadable, corrupted, or from another case.
class CheckpointError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Writes the whole scene: in one process sim.whole_scene(); in a distributed run with shared
// files (output_share.hpp) every rank calls it and writes its owned points' rows, otherwise rank 0
// writes its whole scene, gathered before. A failure in a file the ranks share ends every rank
// (hdf5::fail).
void write_checkpoint(const std::string& path, const Simulation& sim);

// Overwrites the state of `sim` (built from the same case) with the checkpoint's: a distributed
// run reads it into its whole scene and each rank takes its part's (a checkpoint written on N
// ranks restarts on M). Throws CheckpointError naming the file and what does not match.
void read_checkpoint(const std::string& path, Simulation& sim);

}  // namespace ckpd
