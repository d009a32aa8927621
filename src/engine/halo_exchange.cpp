#include "src/engine/halo_exchange.hpp"

namespace ckpd {

namespace {

// Sizes the per-rank buffers: send[q] for `out[q]` points, receive[q] for `in[q]` points, of
// `values` doubles each (no allocation once they have held as much).
void size_buffers(const std::vector<std::vector<std::uint32_t>>& out,
                  const std::vector<std::vector<std::uint32_t>>& in, std::size_t values,
                  HaloBuffers& buffers) {
  buffers.send.resize(out.size());
  buffers.receive.resize(in.size());
  for (std::size_t q = 0; q < out.size(); ++q) buffers.send[q].resize(values * out[q].size());
  for (std::size_t q = 0; q < in.size(); ++q) buffers.receive[q].resize(values * in[q].size());
}

}  // namespace

void pack_state(const HaloLinks& links, const Body& body, HaloBuffers& buffers) {
  size_buffers(links.send, links.receive, kStateValues, buffers);
  for (std::size_t q = 0; q < links.send.size(); ++q) {
    double* v = buffers.send[q].data();
    for (const std::uint32_t k : links.send[q]) {
      for (int c = 0; c < 3; ++c) *v++ = body.displacement[k][c];
      for (int c = 0; c < 3; ++c) *v++ = body.velocity[k][c];
    }
  }
}

void unpack_state(const HaloLinks& links, const HaloBuffers& buffers, Body& body) {
  for (std::size_t q = 0; q < links.receive.size(); ++q) {
    const double* v = buffers.receive[q].data();
    for (const std::uint32_t k : links.receive[q]) {
      for (int c = 0; c < 3; ++c) body.displacement[k][c] = *v++;
      for (int c = 0; c < 3; ++c) body.velocity[k][c] = *v++;
    }
  }
}

void pack_ghost_forces(const HaloLinks& links, const Body& body, bool with_energy,
                       HaloBuffers& buffers) {
  // Backward the roles swap: the ghosts go out, the own points sent forward come back.
  size_buffers(links.receive, links.send, force_values(with_energy), buffers);
  for (std::size_t q = 0; q < links.receive.size(); ++q) {
    double* v = buffers.send[q].data();
    for (const std::uint32_t k : links.receive[q]) {
      for (int c = 0; c < 3; ++c) *v++ = body.force_density[k][c];
      if (with_energy) *v++ = body.strain_energy_density[k];
    }
  }
}

void add_owner_forces(const HaloLinks& links, int rank, HaloBuffers& buffers, bool with_energy,
                      Body& body) {
  const std::size_t n = body.size();
  buffers.own_force.resize(n);
  if (with_energy) buffers.own_energy.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    if (links.owned[k] == 0) continue;
    buffers.own_force[k] = body.force_density[k];
    body.force_density[k] = Vec3::Zero();
    if (with_energy) {
      buffers.own_energy[k] = body.strain_energy_density[k];
      body.strain_energy_density[k] = 0;
    }
  }
  // Rank by rank, so that every owned point gets its partials in rank order.
  const std::size_t values = force_values(with_energy);
  for (std::size_t q = 0; q < links.send.size(); ++q) {
    if (q == static_cast<std::size_t>(rank)) {
      for (std::size_t k = 0; k < n; ++k) {
        if (links.owned[k] == 0) continue;
        body.force_density[k] += buffers.own_force[k];
        if (with_energy) body.strain_energy_density[k] += buffers.own_energy[k];
      }
      continue;
    }
    const double* v = buffers.receive[q].data();
    for (const std::uint32_t k : links.send[q]) {
      body.force_density[k] += Vec3(v[0], v[1], v[2]);
      if (with_energy) body.strain_energy_density[k] += v[3];
      v += values;
    }
  }
}

}  // namespace ckpd
