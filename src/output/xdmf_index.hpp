#pragma once
// The XDMF indexes of a run's field frames (field_writer.hpp writes the frames):
// - DIR/fields.xdmf: a temporal collection of spatial collections, one frame a time step and
//   one block per body, named by the body (ParaView's three XDMF readers);
// - DIR/fields_<body>.xdmf, one per body: a temporal collection of that body's grids, the form
//   meshio's XDMF TimeSeriesReader reads (its points and cells from the first frame, each
//   frame's fields, the current position among them, as point data). The grids are named by
//   the body.
// Heavy-data paths are relative to the XDMF files (fields/frame_NNNNNN.h5:/body_B/...).
#include <cstddef>
#include <string>
#include <vector>

namespace ckpd {

// One frame as the indexes list it.
struct FrameRecord {
  std::string file;  // relative to the output directory
  double time = 0;
  std::vector<std::size_t> points;     // per body: points, or a wall's surface vertices
  std::vector<std::size_t> triangles;  // per body: 0 for a point body
};

// The text of DIR/fields.xdmf: every body of every frame. `fields`: the written fields, position
// first.
std::string run_xdmf(const std::vector<FrameRecord>& frames, const std::vector<std::string>& bodies,
                     const std::vector<std::string>& fields);

// The text of body `b`'s series (`bodies[b]` names it).
std::string body_xdmf(const std::vector<FrameRecord>& frames,
                      const std::vector<std::string>& bodies, std::size_t b,
                      const std::vector<std::string>& fields);

// Each body's series file name in the output directory: fields_<name>.xdmf, the name's
// characters other than letters, digits, '-', '_' and '.' as '_', and with the body's index
// (fields_<name>_<b>.xdmf) where two bodies would share one.
std::vector<std::string> body_xdmf_names(const std::vector<std::string>& bodies);

}  // namespace ckpd
