#include "src/output/output_share.hpp"

#include <stdexcept>

#include "src/engine/distribution.hpp"
#include "src/engine/ranks.hpp"

namespace ckpd {

bool shared_output(const Simulation& sim) {
  return sim.distribution() != nullptr && hdf5::shared_files() && ranks::count() > 1 &&
         !sim.scene().output.gather_files;
}

const Scene& output_scene(const Simulation& sim) {
  return shared_output(sim) ? sim.scene() : sim.whole_scene();
}

hdf5::RowShare alike_rows(const Simulation& sim, std::size_t rows) {
  return shared_output(sim) && !ranks::root() ? hdf5::RowShare::none(rows)
                                              : hdf5::RowShare::all(rows);
}

namespace {

// Appends point `local` of share.body, point `whole` of the whole body `of`, to the share.
void add_point(BodyShare& share, const Body& of, std::size_t local, std::size_t whole) {
  share.local.push_back(static_cast<std::uint32_t>(local));
  share.points.add(whole, 1);
  if (of.family.offset.size() == of.size() + 1 && !of.bond_intact.empty())
    share.bonds.add(of.family.offset[whole], of.family.offset[whole + 1] - of.family.offset[whole]);
}

BodyShare empty_share(const Body& whole) {
  BodyShare share;
  share.points = hdf5::RowShare::none(whole.size());
  share.bonds = hdf5::RowShare::none(whole.bond_intact.size());
  return share;
}

}  // namespace

std::string output_files_text(bool distributed, bool gathered) {
  return distributed && hdf5::shared_files() && !gathered
             ? "written by every rank into shared files, each its own points (parallel HDF5)"
             : "gathered to rank 0, which writes them";
}

BodyShare whole_body_share(const Body& body) {
  BodyShare share = empty_share(body);
  share.body = &body;
  for (std::size_t i = 0; i < body.size(); ++i) add_point(share, body, i, i);
  return share;
}

BodyShare body_share(const Simulation& sim, std::size_t b) {
  const Body& whole = sim.whole_scene().bodies[b].body;
  if (!shared_output(sim)) return whole_body_share(whole);
  BodyShare share = empty_share(whole);
  const DistributedBody& db = sim.distribution()->body(b);
  share.body = &sim.scene().bodies[b].body;
  if (db.replicated) {  // every rank holds it whole; rank 0 writes it
    if (ranks::root())
      for (std::size_t i = 0; i < whole.size(); ++i) add_point(share, whole, i, i);
    return share;
  }
  if (share.body->size() != db.links.points.size() || db.whole_points != whole.size())
    throw std::logic_error("output: body '" + whole.name + "' is not the one this rank's part of");
  share.whole_of_local = &db.links.points;
  for (std::size_t l = 0; l < db.links.points.size(); ++l)
    if (db.links.owned[l]) add_point(share, whole, l, db.links.points[l]);
  return share;
}

std::vector<std::uint8_t> bond_rows(const BodyShare& share) {
  const Body& body = *share.body;
  std::vector<std::uint8_t> out;
  out.reserve(share.bonds.mine());
  if (body.family.offset.size() != body.size() + 1 || body.bond_intact.empty()) return out;
  for (std::size_t l : share.local)
    out.insert(out.end(),
               body.bond_intact.begin() + static_cast<std::ptrdiff_t>(body.family.offset[l]),
               body.bond_intact.begin() + static_cast<std::ptrdiff_t>(body.family.offset[l + 1]));
  if (out.size() != share.bonds.mine())
    throw std::logic_error("output: body '" + body.name +
                           "': a rank's part does not hold its points' whole families");
  return out;
}

}  // namespace ckpd
