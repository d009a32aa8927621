#include "src/output/checkpoint.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "src/engine/distribution.hpp"
#include "src/engine/ranks.hpp"
#include "src/output/content_hash.hpp"
#include "src/output/durable_file.hpp"
#include "src/output/hdf5_io.hpp"
#include "src/output/output_share.hpp"

namespace ckpd {

namespace {

// Format 4: the content hash and the case's physics text (format 1 had neither), rigid states with
// the contact couple, and the contact group with the DEM laws' springs (format 2 had no couple
// or springs). Format 4 hashes each point's row on its own and adds the rows' hashes, so that the
// ranks of a distributed run can hash the rows they write (format 3 hashed the arrays in one
// sequence; still read). Older formats are refused.
constexpr const char* kFormat = "ckpd checkpoint 4";
constexpr const char* kFormat3 = "ckpd checkpoint 3";
constexpr std::size_t kRigidState = 16;
using hdf5::Handle;

void hash_counters(ContentHash& h, double dt, const Simulation::Counters& c, bool adaptive) {
  h.value(dt);
  h.value(c.time);
  h.value(c.step);
  h.value(c.external_work);
  h.value(c.dissipated);
  h.value(c.strain_energy);
  h.value(c.initial_total);
  if (adaptive) {  // a fixed-step checkpoint hashes as before
    h.value(c.next_dt);
    h.value(c.smallest_step);
    h.value(c.reduced_steps);
  }
}

// Format 4: the sum (modulo 2^64) over the share's points of each point's hash of its body and
// whole-body index, its state and its bond flags, so that any split of the rows over ranks gives
// the same sum, and a changed byte changes its row's hash and with it the sum.
std::uint64_t point_rows_hash(const BodyShare& share, std::size_t b) {
  const Body& body = *share.body;
  const bool families = body.family.offset.size() == body.size() + 1 && !body.bond_intact.empty();
  std::uint64_t sum = 0;
  for (std::size_t k = 0; k < share.local.size(); ++k) {
    const std::size_t l = share.local[k];
    ContentHash h;
    h.value(b);
    h.value(share.whole_index(k));
    h.value(body.displacement[l]);
    h.value(body.velocity[l]);
    h.value(body.acceleration[l]);
    h.value(body.force_density[l]);
    h.value(body.external_force_density[l]);
    h.value(body.strain_energy_density[l]);
    if (families)
      h.bytes(body.bond_intact.data() + body.family.offset[l],
              body.family.offset[l + 1] - body.family.offset[l]);
    sum += h.value();
  }
  return sum;
}

// Format 3: the body's arrays in one sequence.
void hash_body(ContentHash& h, const Body& body, std::size_t initially_failed) {
  h.text(body.name);
  h.value(initially_failed);
  h.vector(body.displacement);
  h.vector(body.velocity);
  h.vector(body.acceleration);
  h.vector(body.force_density);
  h.vector(body.external_force_density);
  h.vector(body.strain_energy_density);
  h.vector(body.bond_intact);
}

// The DEM laws' state: evaluation count, dissipated energies and every spring row.
void hash_contact(ContentHash& h, const ContactManager::HistoryState& state) {
  h.value(state.evaluation);
  h.value(state.damping_dissipated);
  h.value(state.friction_dissipated);
  h.value(state.rows.size());
  for (const ContactHistoryRow& r : state.rows) {
    h.value(r.body);
    h.value(r.point);
    h.value(r.partner_body);
    h.value(r.partner_point);
    h.bytes(r.spring.data(), 3 * sizeof(double));
  }
}

std::string format_seconds(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

std::string node_summary(const YAML::Node& n) {
  if (!n) return "absent";
  if (n.IsScalar()) return "'" + n.Scalar() + "'";
  std::string text = YAML::Dump(n);
  for (char& c : text)
    if (c == '\n') c = ' ';
  if (text.size() > 60) text = text.substr(0, 57) + "...";
  return text;
}

// The first key path where two physics documents differ, with both values.
std::string first_difference(const YAML::Node& a, const YAML::Node& b, const std::string& path) {
  const std::string here = path.empty() ? "(top level)" : path;
  if (!a || !b || a.Type() != b.Type())
    return here + ": " + node_summary(a) + " in the checkpoint, " + node_summary(b) + " here";
  if (a.IsScalar())
    return a.Scalar() == b.Scalar()
               ? ""
               : here + ": " + node_summary(a) + " in the checkpoint, " + node_summary(b) + " here";
  if (a.IsSequence()) {
    if (a.size() != b.size())
      return here + ": a list of " + std::to_string(a.size()) + " in the checkpoint, of " +
             std::to_string(b.size()) + " here";
    for (std::size_t i = 0; i < a.size(); ++i) {
      const std::string d = first_difference(a[i], b[i], path + "[" + std::to_string(i) + "]");
      if (!d.empty()) return d;
    }
    return "";
  }
  if (a.IsMap()) {
    for (const auto& kv : a) {
      const std::string key = kv.first.Scalar();
      const std::string d =
          first_difference(kv.second, b[key], path.empty() ? key : path + "." + key);
      if (!d.empty()) return d;
    }
    for (const auto& kv : b) {
      const std::string key = kv.first.Scalar();
      if (!a[key])
        return (path.empty() ? key : path + "." + key) + ": absent in the checkpoint, " +
               node_summary(kv.second) + " here";
    }
  }
  return "";
}

template <class T>
void require_finite(const std::string& path, const std::string& what, const std::vector<T>& v) {
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!v[i].allFinite())
      throw CheckpointError(path + ": " + what + " of point " + std::to_string(i) +
                            " is not finite (corrupted checkpoint)");
}

void require_finite(const std::string& path, const std::string& what, double v) {
  if (!std::isfinite(v))
    throw CheckpointError(path + ": " + what + " is not finite (corrupted checkpoint)");
}

}  // namespace

void write_checkpoint(const std::string& path, const Simulation& sim) {
  hdf5::silence_errors();
  // A shared file (output_share.hpp): every rank writes the rows of its owned points; every
  // rank holds the same counters, rigid states and contact books, so all write the same
  // attributes. Rank 0 renames the file.
  const bool shared = shared_output(sim);
  const std::string temp = partial_path(path);
  const hdf5::SharedWrite collective(shared);  // a failure ends every rank
  try {
    Handle file(shared ? hdf5::create_shared_file(temp)
                       : H5Fcreate(temp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
                H5Fclose, "create " + temp);
    const Simulation::Counters c = sim.counters();
    ContentHash hash;
    std::uint64_t rows_hash = 0;
    hash_counters(hash, sim.step_choice().dt, c, sim.adaptive());
    hdf5::write_string_attribute(file, "format", kFormat);
    hdf5::write_string_attribute(file, "case_fingerprint", sim.whole_scene().fingerprint);
    hdf5::write_string_attribute(file, "case_physics", sim.whole_scene().physics);
    hdf5::write_double_attribute(file, "dt", sim.step_choice().dt);
    hdf5::write_double_attribute(file, "time", c.time);
    hdf5::write_int64_attribute(file, "step", c.step);
    hdf5::write_double_attribute(file, "external_work", c.external_work);
    hdf5::write_double_attribute(file, "dissipated", c.dissipated);
    hdf5::write_double_attribute(file, "strain_energy", c.strain_energy);
    hdf5::write_double_attribute(file, "initial_total", c.initial_total);
    if (sim.adaptive()) {
      // The adaptive step's own counters: the next step (as chosen, before a clip to time.end),
      // the smallest step and the steps below dt (smallest_step is +inf before any).
      hdf5::write_double_attribute(file, "adaptive_next_dt", c.next_dt);
      hdf5::write_double_attribute(file, "adaptive_smallest_step", c.smallest_step);
      hdf5::write_int64_attribute(file, "adaptive_reduced_steps", c.reduced_steps);
    }
    const auto& bodies = output_scene(sim).bodies;
    hdf5::write_int64_attribute(file, "bodies", static_cast<long long>(bodies.size()));
    for (std::size_t b = 0; b < bodies.size(); ++b) {
      const BodyShare share = body_share(sim, b);
      const Body& body = *share.body;
      Handle group(H5Gcreate2(file, ("body_" + std::to_string(b)).c_str(), H5P_DEFAULT, H5P_DEFAULT,
                              H5P_DEFAULT),
                   H5Gclose, "create a body group");
      hdf5::write_string_attribute(group, "name", body.name);
      hdf5::write_int64_attribute(group, "points", static_cast<long long>(share.points.rows));
      hdf5::write_int64_attribute(group, "initially_failed",
                                  static_cast<long long>(c.initially_failed[b]));
      std::vector<Vec3> cut;
      const auto vectors = [&](const char* name, const std::vector<Vec3>& v) {
        hdf5::write_vectors(group, name, rows_of(share, v, 1, cut), share.points);
      };
      vectors("displacement", body.displacement);
      vectors("velocity", body.velocity);
      vectors("acceleration", body.acceleration);
      vectors("force_density", body.force_density);
      vectors("external_force_density", body.external_force_density);
      std::vector<double> cut_densities;
      hdf5::write_doubles(group, "strain_energy_density",
                          rows_of(share, body.strain_energy_density, 1, cut_densities).data(),
                          share.points, 1);
      hdf5::write_bytes(group, "bond_intact", bond_rows(share), share.bonds);
      hash.text(body.name);
      hash.value(c.initially_failed[b]);
      rows_hash += point_rows_hash(share, b);
      if (const auto& rigid = bodies[b].rigid) {
        const RigidMotion::State r = rigid->state();
        const double packed[kRigidState] = {r.centre.x(),           r.centre.y(),
                                            r.centre.z(),           r.velocity.x(),
                                            r.velocity.y(),         r.velocity.z(),
                                            r.angular_momentum.x(), r.angular_momentum.y(),
                                            r.angular_momentum.z(), r.orientation.w(),
                                            r.orientation.x(),      r.orientation.y(),
                                            r.orientation.z(),      r.couple.x(),
                                            r.couple.y(),           r.couple.z()};
        hdf5::write_doubles(group, "rigid_state", packed, alike_rows(sim, kRigidState), 1);
        hash.bytes(packed, sizeof packed);
      }
      group.close();
    }
    if (sim.contact()) {
      // Evaluation count, dissipation and one row per spring: the pair's four indices (the
      // wall partner's point as -1) and the spring.
      const ContactManager::HistoryState h = sim.contact_history();
      // Springs (friction) keep a run on replicated state (distribution.hpp): none here.
      if (shared && ranks::any(!h.rows.empty()))
        throw std::logic_error("checkpoint: contact springs in a distributed run");
      Handle group(H5Gcreate2(file, "contact", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                   "create contact group");
      hdf5::write_int64_attribute(group, "evaluation", static_cast<long long>(h.evaluation));
      hdf5::write_double_attribute(group, "damping_dissipated", h.damping_dissipated);
      hdf5::write_double_attribute(group, "friction_dissipated", h.friction_dissipated);
      hdf5::write_int64_attribute(group, "springs", static_cast<long long>(h.rows.size()));
      hash_contact(hash, h);
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
      group.close();
    }
    hash.value(shared ? ranks::sum_wrapping(rows_hash) : rows_hash);
    hdf5::write_string_attribute(file, "content_hash", hash.hex());
    hdf5::flush_file(file, temp);
    file.close();
  } catch (const std::runtime_error& e) {
    std::remove(temp.c_str());
    throw OutputError(path + ": cannot write the checkpoint: " + e.what() + "; " +
                      (std::filesystem::exists(path) ? "the previous checkpoint is unchanged"
                                                     : "there is no checkpoint"));
  }
  if (shared && !ranks::root()) return;
  try {
    replace_file(temp, path, "the checkpoint");
  } catch (const OutputError& e) {
    if (shared) hdf5::fail(e.what());  // the other ranks went on: end every rank
    throw;
  }
}

void read_checkpoint(const std::string& path, Simulation& sim) {
  hdf5::silence_errors();
  if (!std::filesystem::is_regular_file(path))
    throw CheckpointError(path + ": checkpoint not found");
  if (H5Fis_hdf5(path.c_str()) <= 0)
    throw CheckpointError(path + ": not an HDF5 file (corrupted, or not a ckpd checkpoint)");
  try {
    Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "open " + path);
    const std::string format = hdf5::read_string_attribute(file, "format");
    if (format == "ckpd checkpoint 1" || format == "ckpd checkpoint 2")
      throw CheckpointError(path + ": written by an older ckpd (" + format +
                            ", without checksums or contact history): run the case again from "
                            "the start");
    if (format != kFormat && format != kFormat3)
      throw CheckpointError(path + ": not a ckpd checkpoint of a known format");
    if (hdf5::read_string_attribute(file, "case_fingerprint") != sim.whole_scene().fingerprint) {
      std::string difference;
      try {
        difference = first_difference(YAML::Load(hdf5::read_string_attribute(file, "case_physics")),
                                      YAML::Load(sim.whole_scene().physics), "");
      } catch (const std::exception&) {
        difference = "";  // an unreadable record of the case: say only that it differs
      }
      throw CheckpointError(
          path +
          ": written by another case (its materials, bodies, "
          "conditions or contact differ from this one's" +
          (difference.empty() ? std::string(")") : "; first: " + difference + ")"));
    }
    const double dt = hdf5::read_double_attribute(file, "dt");
    if (dt != sim.step_choice().dt)
      throw CheckpointError(path + ": written with dt = " + format_seconds(dt) +
                            " s, this case gives " + format_seconds(sim.step_choice().dt) +
                            " s (a restart must keep the time step)");
    Scene& scene = sim.whole_scene();
    if (hdf5::read_int64_attribute(file, "bodies") != static_cast<long long>(scene.bodies.size()))
      throw CheckpointError(path + ": holds another number of bodies");
    Simulation::Counters c;
    c.time = hdf5::read_double_attribute(file, "time");
    c.step = hdf5::read_int64_attribute(file, "step");
    c.external_work = hdf5::read_double_attribute(file, "external_work");
    c.dissipated = hdf5::read_double_attribute(file, "dissipated");
    c.strain_energy = hdf5::read_double_attribute(file, "strain_energy");
    c.initial_total = hdf5::read_double_attribute(file, "initial_total");
    const bool adaptive = H5Aexists(file, "adaptive_next_dt") > 0;
    if (adaptive != sim.adaptive())
      throw CheckpointError(path + ": written by a run with " +
                            (adaptive ? "time.step_mode: adaptive" : "a fixed step") +
                            ", this case has " +
                            (sim.adaptive() ? "time.step_mode: adaptive" : "a fixed step") +
                            " (a restart must keep the step's mode)");
    if (adaptive) {
      c.next_dt = hdf5::read_double_attribute(file, "adaptive_next_dt");
      c.smallest_step = hdf5::read_double_attribute(file, "adaptive_smallest_step");
      c.reduced_steps = hdf5::read_int64_attribute(file, "adaptive_reduced_steps");
      if (!(c.next_dt > 0 && c.next_dt <= dt) || !(c.smallest_step > 0) || c.reduced_steps < 0 ||
          c.reduced_steps > std::max(c.step, 0LL))
        throw CheckpointError(path + ": adaptive step counters (next step " +
                              format_seconds(c.next_dt) + " s, " + std::to_string(c.reduced_steps) +
                              " reduced steps) that no run gives (corrupted checkpoint)");
    }
    // Value checks before the hash: they name what is wrong.
    require_finite(path, "the time", c.time);
    require_finite(path, "the external work", c.external_work);
    require_finite(path, "the dissipated energy", c.dissipated);
    require_finite(path, "the strain energy", c.strain_energy);
    require_finite(path, "the initial total energy", c.initial_total);
    // The time is the sum of `step` steps of dt, up to round-off, except that the last step of a
    // run may be shortened to land on time.end: (step - 1) dt < time <= step dt.
    // With an adaptive step, each step is at most dt: 0 < time <= step dt.
    const double full = static_cast<double>(c.step) * dt, slack = 1e-6 * std::max(c.time, dt);
    if (c.step < 0 || !(c.time >= 0) || c.time > full + slack ||
        (!adaptive && c.step > 0 && c.time <= full - dt - slack) ||
        (adaptive && c.step > 0 && !(c.time > 0)))
      throw CheckpointError(
          path + ": step " + std::to_string(c.step) + " and time " + format_seconds(c.time) +
          " s do not agree with dt = " + format_seconds(dt) + " s (corrupted checkpoint)");
    ContentHash hash;
    std::uint64_t rows_hash = 0;
    hash_counters(hash, dt, c, adaptive);
    for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
      Body& body = scene.bodies[b].body;
      Handle group(H5Gopen2(file, ("body_" + std::to_string(b)).c_str(), H5P_DEFAULT), H5Gclose,
                   "open body group " + std::to_string(b));
      if (hdf5::read_string_attribute(group, "name") != body.name ||
          hdf5::read_int64_attribute(group, "points") != static_cast<long long>(body.size()))
        throw CheckpointError(path + ": body " + std::to_string(b) + " does not match '" +
                              body.name + "'");
      const long long failed = hdf5::read_int64_attribute(group, "initially_failed");
      if (failed < 0 || static_cast<unsigned long long>(failed) > body.bond_intact.size())
        throw CheckpointError(path + ": body '" + body.name + "': initially_failed = " +
                              std::to_string(failed) + " is not a bond count from 0 to " +
                              std::to_string(body.bond_intact.size()) + " (corrupted checkpoint)");
      c.initially_failed.push_back(static_cast<std::size_t>(failed));
      const std::size_t n = body.size();
      body.displacement = hdf5::read_vectors(group, "displacement", n);
      body.velocity = hdf5::read_vectors(group, "velocity", n);
      body.acceleration = hdf5::read_vectors(group, "acceleration", n);
      body.force_density = hdf5::read_vectors(group, "force_density", n);
      body.external_force_density = hdf5::read_vectors(group, "external_force_density", n);
      body.strain_energy_density = hdf5::read_doubles(group, "strain_energy_density", n);
      body.bond_intact = hdf5::read_bytes(group, "bond_intact", body.bond_intact.size());
      const std::string where = path + ": body '" + body.name + "'";
      require_finite(where, "the displacement", body.displacement);
      require_finite(where, "the velocity", body.velocity);
      require_finite(where, "the acceleration", body.acceleration);
      require_finite(where, "the force density", body.force_density);
      require_finite(where, "the external force density", body.external_force_density);
      for (std::size_t i = 0; i < n; ++i)
        require_finite(where, "the strain-energy density of point " + std::to_string(i),
                       body.strain_energy_density[i]);
      for (std::size_t k = 0; k < body.bond_intact.size(); ++k)
        if (body.bond_intact[k] > 1)
          throw CheckpointError(where + ": bond_intact[" + std::to_string(k) +
                                "] = " + std::to_string(body.bond_intact[k]) +
                                ", not 0 (broken) or 1 (intact) (corrupted checkpoint)");
      if (format == kFormat3) {
        hash_body(hash, body, c.initially_failed.back());
      } else {
        hash.text(body.name);
        hash.value(c.initially_failed.back());
        rows_hash += point_rows_hash(whole_body_share(body), b);
      }
      if (auto& rigid = scene.bodies[b].rigid) {
        // centre, velocity, angular momentum, orientation quaternion (w, x, y, z), couple
        const std::vector<double> p = hdf5::read_doubles(group, "rigid_state", kRigidState);
        for (double v : p) require_finite(where, "the rigid-body state", v);
        hash.bytes(p.data(), p.size() * sizeof(double));
        rigid->restore({Vec3(p[0], p[1], p[2]), Vec3(p[3], p[4], p[5]), Vec3(p[6], p[7], p[8]),
                        Eigen::Quaterniond(p[9], p[10], p[11], p[12]), Vec3(p[13], p[14], p[15])});
      }
    }
    ContactManager::HistoryState h;
    if (sim.contact()) {
      Handle group(H5Gopen2(file, "contact", H5P_DEFAULT), H5Gclose, "open contact group");
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
      hash_contact(hash, h);
    }
    if (format != kFormat3) hash.value(rows_hash);
    if (hdf5::read_string_attribute(file, "content_hash") != hash.hex())
      throw CheckpointError(path +
                            ": the content hash does not match the stored one (the file "
                            "was changed or corrupted after it was written)");
    // A distributed run read the file into the whole scene: each rank takes its part's state.
    if (const Distribution* d = sim.distribution()) d->scatter(scene, sim.scene());
    sim.restore(c);
    if (sim.contact()) {
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
