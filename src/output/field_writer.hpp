#pragma once
// Field output for ParaView, meshio and h5py: one HDF5 file per output frame
// (DIR/fields/frame_NNNNNN.h5, one group per body, its name an attribute) and the XDMF indexes of
// xdmf_index.hpp: DIR/fields.xdmf (every body, for ParaView) and DIR/fields_<body>.xdmf (one
// body's time series, for meshio). A point body is a Polyvertex grid with explicit connectivity
// (0..N-1: the Xdmf3 readers build no cells without it); a mesh wall is a Triangle grid of its
// surface, moved with the wall's rigid motion. The fields are the rows of
// src/output/field_table.hpp. A frame carries a content hash over its rows and attributes
// (checked when a restart keeps it). Each frame file and each index is written under a temporary
// name, every write checked to the file's close, synced and renamed when complete
// (durable_file.hpp), so a run killed at any moment, or whose disk fills up, leaves every
// complete frame readable and indexed; a write that fails throws OutputError. The ranks of a
// distributed run with parallel HDF5 write each frame together, each its own points
// (output_share.hpp); rank 0 alone names, renames and indexes the frames.
#include <string>
#include <vector>

#include "src/engine/simulation.hpp"
#include "src/output/field_table.hpp"
#include "src/output/xdmf_index.hpp"

namespace ckpd {

class FieldWriter {
 public:
  // `fields`: names from known_field_names() (position is always written: ParaView needs it).
  // A mesh wall gets position, reference_position, displacement, body_id and point_id (its
  // vertex index) of its surface vertices, where asked for; other fields are point fields only.
  // Throws std::invalid_argument for an unknown name, std::runtime_error when `directory`
  // cannot be written.
  // With `resume_after_step` >= 0 (a restart), frames already in the directory up to that step
  // (those whose content hash holds) are kept, the indexes rewritten at once to list them and
  // numbering continues after them; otherwise earlier frames and indexes are removed.
  FieldWriter(std::string directory, const std::vector<std::string>& fields,
              long long resume_after_step);
  // In a run whose ranks share the frame files (output_share.hpp), a rank other than 0: it writes
  // its points into the frames that rank 0's writer (which kept `kept` frames of a run it
  // continues) names, and touches no other file.
  static FieldWriter follower(std::string directory, const std::vector<std::string>& fields,
                              std::size_t kept);

  // Writes the current state as the next frame.
  void write_frame(const Simulation& sim);

  // Whether strain_energy_density is written (it needs an energy evaluation on frame steps).
  bool needs_energy() const;
  std::size_t frames() const { return frames_.size(); }
  // A rank other than 0 whose frames rank 0 writes alone: one more frame was written.
  void count_frame() { frames_.emplace_back(); }

  // The file name of frame `index` in DIR/fields.
  static std::string frame_name(std::size_t index);
  // Reads a frame file back: its record (file relative to the output directory) and body names.
  // Throws std::runtime_error when it is unreadable or its content hash does not match (a frame
  // written without one, by an older ckpd, is only read).
  static FrameRecord read_frame(const std::string& directory, std::size_t index,
                                long long* step = nullptr,
                                std::vector<std::string>* bodies = nullptr);

 private:
  struct ListOnly {};  // checks the field list, touches no file
  FieldWriter(ListOnly, std::string directory, const std::vector<std::string>& fields);
  // Rewrites DIR/fields.xdmf and each body's series.
  void write_indexes() const;

  std::string directory_;
  std::vector<std::string> fields_;
  std::vector<FrameRecord> frames_;
  std::vector<std::string> bodies_;  // the bodies' names, in order
};

}  // namespace ckpd
