#pragma once
// Who sends which points to whom in a halo exchange (issue 14, distributed memory;
// docs/SCALING.md). A rank holds one body as its restriction to the points it owns and their halo
// (bodies/ sub_body.hpp): its ghosts are the halo points other ranks own. Each step the owners send
// their ghosts' state in (positions, and velocities for the damage booking), and after the kernel
// the ranks send the partial forces their sets put on ghosts back to the owners, which add them in
// rank order (the order of force_sharing's replicated sum, so the two schemes agree bit for bit
// at one thread).
//
// From rank r's side, per other rank q: `receive[q]` are the local indices of r's ghosts that q
// owns, `send[q]` the local indices of r's own points that are ghosts on q (an owned point of r
// in the family of a point q owns), both in increasing global index, so rank r's send[q] and rank
// q's receive[r] name the same points in the same order and a message needs no indices.
#include <cstdint>
#include <vector>

#include "bodies/body.hpp"

namespace ckpd {

struct HaloLinks {
  std::vector<std::uint32_t> points;  // the restriction: global indices, increasing
  std::vector<std::uint8_t> owned;    // per local point: 1 owned by this rank, 0 a ghost
  std::vector<std::vector<std::uint32_t>> receive, send;  // per rank (empty for this rank)
  std::uint64_t ghosts() const;                           // points received, all ranks
  std::uint64_t sent() const;                             // points sent, all ranks (with repeats)
  int neighbours() const;                                 // ranks exchanged with
};

// Rank `rank`'s links for `body`, whose point i is owned by owner[i] (0 <= owner < ranks).
// O(bonds). Throws std::invalid_argument when owner has the wrong size or a rank out of range.
HaloLinks halo_links(const Body& body, const std::vector<int>& owner, int rank, int ranks);

}  // namespace ckpd
