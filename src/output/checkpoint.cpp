#include "src/output/checkpoint.hpp"

#include <filesystem>

#include "src/output/hdf5_io.hpp"

namespace ckpd {

namespace {

// 2: rigid states carry the contact couple; the contact group holds the DEM laws' springs.
constexpr const char* kFormat = "ckpd checkpoint 2";
constexpr std::size_t kRigidState = 16;
using hdf5::Handle;

}  // namespace

void write_checkpoint(const std::string& path, const Simulation& sim) {
  hdf5::silence_errors();
  const std::string temp = path + ".partial";
  {
    Handle file(H5Fcreate(temp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose,
                "create " + temp);
    const Simulation::Counters c = sim.counters();
    hdf5::write_string_attribute(file, "format", kFormat);
    hdf5::write_string_attribute(file, "case_fingerprint", sim.scene().fingerprint);
    hdf5::write_double_attribute(file, "dt", sim.step_choice().dt);
    hdf5::write_double_attribute(file, "time", c.time);
    hdf5::write_int64_attribute(file, "step", c.step);
    hdf5::write_double_attribute(file, "external_work", c.external_work);
    hdf5::write_double_attribute(file, "dissipated", c.dissipated);
    hdf5::write_double_attribute(file, "strain_energy", c.strain_energy);
    hdf5::write_double_attribute(file, "initial_total", c.initial_total);
    hdf5::write_int64_attribute(file, "bodies", static_cast<long long>(sim.scene().bodies.size()));
    for (std::size_t b = 0; b < sim.scene().bodies.size(); ++b) {
      const Body& body = sim.scene().bodies[b].body;
      Handle group(H5Gcreate2(file, ("body_" + std::to_string(b)).c_str(), H5P_DEFAULT, H5P_DEFAULT,
                              H5P_DEFAULT),
                   H5Gclose, "create a body group");
      hdf5::write_string_attribute(group, "name", body.name);
      hdf5::write_int64_attribute(group, "points", static_cast<long long>(body.size()));
      hdf5::write_int64_attribute(group, "initially_failed",
                                  static_cast<long long>(c.initially_failed[b]));
      hdf5::write_vectors(group, "displacement", body.displacement);
      hdf5::write_vectors(group, "velocity", body.velocity);
      hdf5::write_vectors(group, "acceleration", body.acceleration);
      hdf5::write_vectors(group, "force_density", body.force_density);
      hdf5::write_vectors(group, "external_force_density", body.external_force_density);
      hdf5::write_doubles(group, "strain_energy_density", body.strain_energy_density.data(),
                          body.size(), 1);
      hdf5::write_bytes(group, "bond_intact", body.bond_intact);
      if (const auto& rigid = sim.scene().bodies[b].rigid) {
        const RigidMotion::State r = rigid->state();
        const double packed[kRigidState] = {r.centre.x(),           r.centre.y(),
                                            r.centre.z(),           r.velocity.x(),
                                            r.velocity.y(),         r.velocity.z(),
                                            r.angular_momentum.x(), r.angular_momentum.y(),
                                            r.angular_momentum.z(), r.orientation.w(),
                                            r.orientation.x(),      r.orientation.y(),
                                            r.orientation.z(),      r.couple.x(),
                                            r.couple.y(),           r.couple.z()};
        hdf5::write_doubles(group, "rigid_state", packed, kRigidState, 1);
      }
    }
    if (const ContactManager* contact = sim.contact()) {
      // Evaluation count, dissipation and one row per spring: the pair's four indices (the
      // wall partner's point as -1) and the spring.
      const ContactManager::HistoryState h = contact->history();
      Handle group(H5Gcreate2(file, "contact", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                   "create contact group");
      hdf5::write_int64_attribute(group, "evaluation", static_cast<long long>(h.evaluation));
      hdf5::write_double_attribute(group, "damping_dissipated", h.damping_dissipated);
      hdf5::write_double_attribute(group, "friction_dissipated", h.friction_dissipated);
      hdf5::write_int64_attribute(group, "springs", static_cast<long long>(h.rows.size()));
      if (!h.rows.empty()) {
        std::vector<double> index;
        std::vector<Vec3> spring;
        for (const ContactHistoryRow& r : h.rows) {
          const double partner = r.partner_point == kWallPartner ? -1.0 : r.partner_point;
          index.insert(index.end(),
                       {double(r.body), double(r.point), double(r.partner_body), partner});
          spring.push_back(r.spring);
        }
        hdf5::write_doubles(group, "spring_index", index.data(), h.rows.size(), 4);
        hdf5::write_vectors(group, "spring", spring);
      }
    }
    if (H5Fflush(file, H5F_SCOPE_GLOBAL) < 0)
      throw std::runtime_error("HDF5: cannot flush " + temp);
  }
  std::error_code ec;
  std::filesystem::rename(temp, path, ec);
  if (ec) throw std::runtime_error(path + ": cannot write the checkpoint: " + ec.message());
}

void read_checkpoint(const std::string& path, Simulation& sim) {
  hdf5::silence_errors();
  if (!std::filesystem::is_regular_file(path))
    throw CheckpointError(path + ": checkpoint not found");
  if (H5Fis_hdf5(path.c_str()) <= 0)
    throw CheckpointError(path + ": not an HDF5 file (corrupted, or not a ckpd checkpoint)");
  try {
    Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "open " + path);
    if (hdf5::read_string_attribute(file, "format") != kFormat)
      throw CheckpointError(path + ": not a ckpd checkpoint of a known format");
    if (hdf5::read_string_attribute(file, "case_fingerprint") != sim.scene().fingerprint)
      throw CheckpointError(path +
                            ": written by another case (its materials, bodies, "
                            "conditions or contact differ from this one's)");
    const double dt = hdf5::read_double_attribute(file, "dt");
    if (dt != sim.step_choice().dt)
      throw CheckpointError(path + ": written with dt = " + std::to_string(dt) +
                            " s, this case gives " + std::to_string(sim.step_choice().dt) +
                            " s (a restart must keep the time step)");
    Scene& scene = sim.scene();
    if (hdf5::read_int64_attribute(file, "bodies") != static_cast<long long>(scene.bodies.size()))
      throw CheckpointError(path + ": holds another number of bodies");
    Simulation::Counters c;
    c.time = hdf5::read_double_attribute(file, "time");
    c.step = hdf5::read_int64_attribute(file, "step");
    c.external_work = hdf5::read_double_attribute(file, "external_work");
    c.dissipated = hdf5::read_double_attribute(file, "dissipated");
    c.strain_energy = hdf5::read_double_attribute(file, "strain_energy");
    c.initial_total = hdf5::read_double_attribute(file, "initial_total");
    for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
      Body& body = scene.bodies[b].body;
      Handle group(H5Gopen2(file, ("body_" + std::to_string(b)).c_str(), H5P_DEFAULT), H5Gclose,
                   "open body group " + std::to_string(b));
      if (hdf5::read_string_attribute(group, "name") != body.name ||
          hdf5::read_int64_attribute(group, "points") != static_cast<long long>(body.size()))
        throw CheckpointError(path + ": body " + std::to_string(b) + " does not match '" +
                              body.name + "'");
      c.initially_failed.push_back(
          static_cast<std::size_t>(hdf5::read_int64_attribute(group, "initially_failed")));
      const std::size_t n = body.size();
      body.displacement = hdf5::read_vectors(group, "displacement", n);
      body.velocity = hdf5::read_vectors(group, "velocity", n);
      body.acceleration = hdf5::read_vectors(group, "acceleration", n);
      body.force_density = hdf5::read_vectors(group, "force_density", n);
      body.external_force_density = hdf5::read_vectors(group, "external_force_density", n);
      body.strain_energy_density = hdf5::read_doubles(group, "strain_energy_density", n);
      body.bond_intact = hdf5::read_bytes(group, "bond_intact", body.bond_intact.size());
      if (auto& rigid = scene.bodies[b].rigid) {
        // centre, velocity, angular momentum, orientation quaternion (w, x, y, z), couple
        const std::vector<double> p = hdf5::read_doubles(group, "rigid_state", kRigidState);
        rigid->restore({Vec3(p[0], p[1], p[2]), Vec3(p[3], p[4], p[5]), Vec3(p[6], p[7], p[8]),
                        Eigen::Quaterniond(p[9], p[10], p[11], p[12]), Vec3(p[13], p[14], p[15])});
      }
    }
    sim.restore(c);
    if (sim.contact()) {
      Handle group(H5Gopen2(file, "contact", H5P_DEFAULT), H5Gclose, "open contact group");
      ContactManager::HistoryState h;
      h.evaluation = static_cast<std::uint64_t>(hdf5::read_int64_attribute(group, "evaluation"));
      h.damping_dissipated = hdf5::read_double_attribute(group, "damping_dissipated");
      h.friction_dissipated = hdf5::read_double_attribute(group, "friction_dissipated");
      const auto rows = static_cast<std::size_t>(hdf5::read_int64_attribute(group, "springs"));
      if (rows > 0) {
        const std::vector<double> index = hdf5::read_doubles(group, "spring_index", 4 * rows);
        const std::vector<Vec3> spring = hdf5::read_vectors(group, "spring", rows);
        for (std::size_t r = 0; r < rows; ++r) {
          const double* x = &index[4 * r];
          h.rows.push_back({static_cast<std::uint32_t>(x[0]), static_cast<std::uint32_t>(x[1]),
                            static_cast<std::uint32_t>(x[2]),
                            x[3] < 0 ? kWallPartner : static_cast<std::uint32_t>(x[3]), spring[r]});
        }
      }
      try {
        sim.restore_contact(h);
      } catch (const std::invalid_argument& e) {
        throw CheckpointError(path + ": " + e.what());
      }
    }
  } catch (const CheckpointError&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw CheckpointError(path + ": unreadable checkpoint (" + e.what() + ")");
  }
}

}  // namespace ckpd
