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

struct BodyShare {
  const Body* body = nullptr;  // the body the rows are taken from (this rank's part, or whole)
  std::size_t whole_points = 0;
  hdf5::RowShare points;           // rows of the per-point arrays
  hdf5::RowShare bonds;            // rows of bond_intact (the points' families, in order)
  std::vector<std::size_t> local;  // the points of `body` whose rows those are, in row order
  std::vector<std::size_t> whole;  // the same points' indices in the whole body
  // Each point of `body`'s index in the whole body (null: `body` is the whole body).
  const std::vector<std::uint32_t>* whole_of_local = nullptr;
};

// Every row of `body`, from `body`.
BodyShare whole_body_share(const Body& body);

// Body `b`'s rows for this process: with shared_output, its owned points of its part; otherwise
// all points of sim.whole_scene()'s body.
BodyShare body_share(const Simulation& sim, std::size_t b);

// values (`columns` per point of share.body) cut to the rows this process writes.
template <class T>
std::vector<T> rows_of(const BodyShare& share, const std::vector<T>& values, std::size_t columns) {
  std::vector<T> out;
  out.reserve(share.local.size() * columns);
  for (std::size_t l : share.local)
    out.insert(out.end(), values.begin() + static_cast<std::ptrdiff_t>(l * columns),
               values.begin() + static_cast<std::ptrdiff_t>((l + 1) * columns));
  return out;
}

// The bond flags of the share's points, family after family (an owned point's family is whole in
// its rank's part, in the whole body's order).
std::vector<std::uint8_t> bond_rows(const BodyShare& share);

}  // namespace ckpd
