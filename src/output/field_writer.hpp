#pragma once
// Field output for ParaView: one HDF5 file per output frame (DIR/fields/frame_NNNNNN.h5, one
// group per body) and DIR/fields.xdmf, a temporal collection of those frames, one block per body
// and the real time values. A point body is a Polyvertex grid with explicit connectivity
// (0..N-1: the Xdmf3 readers build no cells without it); a mesh wall is a Triangle grid of its
// surface, moved with the wall's rigid motion. Heavy-data paths are relative to the XDMF file.
// The fields are the rows of src/output/field_table.hpp. Each frame file is written under
// a temporary name and renamed when complete, and the XDMF is rewritten the same way after each
// frame, so a run killed at any moment leaves every complete frame readable. The ranks of a
// distributed run with parallel HDF5 write each frame together, each its own points
// (output_share.hpp); rank 0 alone names, renames and indexes the frames.
#include <string>
#include <vector>

#include "src/engine/simulation.hpp"
#include "src/output/field_table.hpp"

namespace ckpd {

class FieldWriter {
 public:
  // `fields`: names from known_field_names() (position is always written: ParaView needs it).
  // A mesh wall gets position, reference_position, displacement, body_id and point_id (its
  // vertex index) of its surface vertices, where asked for; other fields are point fields only.
  // Throws std::invalid_argument for an unknown name, std::runtime_error when `directory`
  // cannot be written.
  // With `resume_after_step` >= 0 (a restart), frames already in the directory up to that step
  // are kept and numbering continues after them; otherwise earlier frames are removed.
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

 private:
  struct Frame {
    std::string file;  // relative to the output directory
    double time;
    std::vector<std::size_t> points;     // per body: points, or a wall's surface vertices
    std::vector<std::size_t> triangles;  // per body: 0 for a point body
  };
  struct ListOnly {};  // checks the field list, touches no file
  FieldWriter(ListOnly, std::string directory, const std::vector<std::string>& fields);
  void write_xdmf(const Simulation& sim) const;
  static std::string frame_name(std::size_t index);

  std::string directory_;
  std::vector<std::string> fields_;
  std::vector<Frame> frames_;
};

}  // namespace ckpd
