#pragma once
// The halo exchange's messages for one body on one rank (issue 14; the lists: halo.hpp), apart
// from how they travel (MPI point to point between ranks, or copied in one process by the tests):
// per other rank q one buffer of doubles, values only, in the lists' order.
//
// Forward, each step before the forces: the owners' displacements and velocities of the points
// that are ghosts elsewhere (velocities: the damage booking evaluates energies at the step's
// midpoint, u - dt/2 v). Backward, after the kernel: the partial forces (and energy densities)
// the rank's sets put on its ghosts, to their owners, which add every rank's partial in rank
// order, their own at their place: the replicated scheme's sum (force_sharing.hpp), bit for bit
// at one thread.
#include <vector>

#include "bodies/body.hpp"
#include "src/engine/halo.hpp"

namespace ckpd {

struct HaloBuffers {
  std::vector<std::vector<double>> send, receive;  // per rank; sized by the pack/expect calls
  std::vector<Vec3> own_force;                     // the rank's own partials while summing
  std::vector<double> own_energy;
};

// Doubles per point in a forward message (displacement, velocity) and a backward one (force,
// and with energy the strain energy density).
inline constexpr std::size_t kStateValues = 6;
inline std::size_t force_values(bool with_energy) {
  return with_energy ? 4 : 3;
}

// Fills buffers.send[q] with the state of the points this rank sends q, and sizes
// buffers.receive[q] for what q sends.
void pack_state(const HaloLinks& links, const Body& body, HaloBuffers& buffers);
// Sets the ghosts' state from buffers.receive.
void unpack_state(const HaloLinks& links, const HaloBuffers& buffers, Body& body);

// Fills buffers.send[q] with the partial forces (and energies) on the ghosts q owns, and sizes
// buffers.receive[q] for what q sends back.
void pack_ghost_forces(const HaloLinks& links, const Body& body, bool with_energy,
                       HaloBuffers& buffers);
// The owned points' forces (and energies) become the sum over ranks in rank order of every
// rank's partial; the ghosts' entries are left as they were (partials, not totals).
void add_owner_forces(const HaloLinks& links, int rank, HaloBuffers& buffers, bool with_energy,
                      Body& body);

}  // namespace ckpd
