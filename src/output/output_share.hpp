#pragma once
// Who writes which rows of a body's arrays into a field frame or checkpoint. One process writes
// every row of the whole body. The ranks of a distributed run (issue 14) on a build with parallel
// HDF5 share the file instead: each rank writes the rows of the points it owns (and of their
// bonds) from its own part of the body, so no rank gathers the scene and the file is the same,
// row for row, as one process writes. Rigid bodies, which every rank holds whole, are written by
// rank 0. Without parallel HDF5 a distributed run gathers to rank 0, which writes alone.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "src/engine/simulation.hpp"
#include "src/output/hdf5_io.hpp"

namespace ckpd {

// Whether this process writes its share of the output files together with the other ranks
// (hdf5::create_shared_file): a distributed run of several ranks on a build with parallel HDF5,
// unless told to gather (OutputSettings::gather_files).
bool shared_output(const Simulation& sim);

// How the ranks of an MPI run write the frames and checkpoints, in words (`distributed`: on
// distributed memory; `gathered`: told to gather, `ckpd run --gather-output`).
std::string output_files_text(bool distributed, bool gathered);

// The scene the rows are taken from: this rank's part with shared_output (its rigid bodies and
// walls moved alike on every rank), otherwise sim.whole_scene().
const Scene& output_scene(const Simulation& sim);

// The rows of something every process holds alike (a rigid state, a wall's surface): all of them
// for one process, and in a shared file rank 0's.
hdf5::RowShare alike_rows(const Simulation& sim, std::size_t rows);

struct BodyShare {
  const Body* body = nullptr;  // the body the rows are taken from (this rank's part, or whole)
  hdf5::RowShare points;       // rows of the per-point arrays (points.rows: the whole body's)
  hdf5::RowShare bonds;        // rows of bond_intact (the points' families, in order)
  std::vector<std::uint32_t> local;  // the points of `body` whose rows those are, in row order
  // Each point of `body`'s index in the whole body (null: `body` is the whole body).
  const std::vector<std::uint32_t>* whole_of_local = nullptr;
  // The whole-body index of the share's k-th point.
  std::size_t whole_index(std::size_t k) const {
    return whole_of_local ? (*whole_of_local)[local[k]] : local[k];
  }
  // Whether the rows are every point of `body`, in order (one process, or rank 0's rigid body).
  bool every_point() const { return local.size() == body->size(); }
};

// Every row of `body`, from `body`.
BodyShare whole_body_share(const Body& body);

// Body `b`'s rows for this process: with shared_output, its owned points of its part; otherwise
// all points of sim.whole_scene()'s body.
BodyShare body_share(const Simulation& sim, std::size_t b);

// values (`columns` per point of share.body) cut to the rows this process writes: `values`
// itself when they are every point's, else the cut, in `scratch`.
template <class T>
const std::vector<T>& rows_of(const BodyShare& share, const std::vector<T>& values,
                              std::size_t columns, std::vector<T>& scratch) {
  if (share.every_point()) return values;
  scratch.clear();
  scratch.reserve(share.local.size() * columns);
  for (std::size_t l : share.local)
    scratch.insert(scratch.end(), values.begin() + static_cast<std::ptrdiff_t>(l * columns),
                   values.begin() + static_cast<std::ptrdiff_t>((l + 1) * columns));
  return scratch;
}

// The bond flags of the share's points, family after family (an owned point's family is whole in
// its rank's part, in the whole body's order).
std::vector<std::uint8_t> bond_rows(const BodyShare& share);

}  // namespace ckpd
