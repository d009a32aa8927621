#include "src/output/run_output.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "bodies/damage.hpp"
#include "bodies/fragments.hpp"
#include "src/output/beta_report.hpp"
#include "src/output/contact_summary.hpp"
#include "src/output/history_quantities.hpp"
#include "src/output/kernel_report.hpp"

namespace ckpd {

namespace {

// The step a history row starts with; false for a line that does not start with a whole number
// and a comma.
bool row_step(const std::string& line, long long& step) {
  const auto comma = line.find(',');
  if (comma == 0 || comma == std::string::npos) return false;
  std::size_t used = 0;
  try {
    step = std::stoll(line.substr(0, comma), &used);
  } catch (const std::exception&) {
    return false;
  }
  return used == comma;
}

}  // namespace

HistoryWriter::HistoryWriter(const std::string& path, long long resume_after_step,
                             std::vector<HistoryQuantity> chosen, bool far_field,
                             long long interval)
    : chosen_(std::move(chosen)), far_field_(far_field) {
  std::string header =
      "step,time,kinetic,strain,contact,external_work,dissipated,contact_damping,"
      "contact_friction,balance_error,broken_bonds,max_damage,inverted";
  for (const HistoryQuantity& q : chosen_)
    for (const std::string& column : history_columns(q)) header += "," + column;
  if (far_field_) header += ",exact_fraction";
  std::string text = header + '\n';
  if (resume_after_step >= 0) {
    std::ifstream in(path);
    const std::string old((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    // Whole lines only (a line without its newline was cut off), each step once, in order.
    std::size_t begin = 0, end = old.find('\n');
    if (end != std::string::npos && old.compare(0, end, header) == 0 && end == header.size()) {
      for (begin = end + 1; (end = old.find('\n', begin)) != std::string::npos; begin = end + 1) {
        const std::string line = old.substr(begin, end - begin);
        long long step = 0;
        if (!row_step(line, step) || step > resume_after_step) break;
        if (step <= last_step_ || step % std::max(interval, 1LL) != 0) continue;
        text += line + '\n';
        last_step_ = step;
      }
    }
  }
  write_file_replacing(path, text, "the history");
  out_ = AppendFile(path, "the history");
}

void HistoryWriter::write_row(const Simulation& sim, const std::vector<double>& chosen) {
  if (sim.step() == last_step_) return;
  const Energies e = sim.energies();
  std::ostringstream row;
  row << std::setprecision(10) << sim.step() << ',' << sim.time() << ',' << e.kinetic << ','
      << e.strain << ',' << e.contact << ',' << e.external_work << ',' << e.dissipated << ','
      << e.contact_damping << ',' << e.contact_friction << ',' << e.balance_error << ','
      << sim.broken_bonds() << ',' << sim.max_damage() << ',' << sim.inverted();
  for (double v : chosen) row << ',' << v;
  if (far_field_) row << ',' << sim.exact_fraction();
  row << '\n';
  out_.append(row.str());
  last_step_ = sim.step();
}

double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

std::string inversion_warning(const Simulation& sim) {
  const InversionRecord& r = sim.first_inversion();
  if (r.step < 0) return "";
  const char* what = "tetrahedra";
  for (const SceneBody& sb : sim.whole_scene().bodies)
    if (sb.body.name == r.body && sb.body.dimension == 2) what = "triangles";
  std::ostringstream msg;
  msg << "model breakdown: " << r.count << " inverted " << what << " in body '" << r.body
      << "' first seen at step " << r.step << ", t = " << r.time
      << " s (counted on history rows): an inverted set resists no more than an upright one "
         "(the energy uses |v|); results past this point are outside the model unless the body "
         "sets inversion_penalty";
  return msg.str();
}

nlohmann::ordered_json inversion_summary(const Simulation& sim) {
  const InversionRecord& r = sim.first_inversion();
  nlohmann::ordered_json j;
  j["final"] = sim.inverted();
  j["max"] = sim.max_inverted();
  if (r.step >= 0) {
    j["first"] = {{"step", r.step}, {"time", r.time}, {"body", r.body}, {"count", r.count}};
    j["warning"] = inversion_warning(sim);
  } else {
    j["first"] = nullptr;
  }
  return j;
}

nlohmann::ordered_json make_summary(const Simulation& sim, const std::string& status,
                                    const std::string& message, double wall_seconds) {
  nlohmann::ordered_json j;
  j["status"] = status;
  if (!message.empty()) j["message"] = message;
  j["case"] = sim.whole_scene().case_file;
  std::uint64_t points = 0, bonds = 0, pairs = 0, triples = 0;
  nlohmann::ordered_json bodies = nlohmann::ordered_json::array();
  for (std::size_t index = 0; index < sim.whole_scene().bodies.size(); ++index) {
    const SceneBody& sb = sim.whole_scene().bodies[index];
    const Body& b = sb.body;
    points += b.size();
    bonds += b.bond_count();
    pairs += b.total_two_neighbour();
    triples += b.total_three_neighbour();
    // A rigid body has no bonds and is one piece.
    const FragmentCensus fragments =
        sb.rigid ? FragmentCensus{std::vector<std::uint32_t>(b.size(), 0), {b.size()}}
                 : find_fragments(b);
    std::vector<std::size_t> sizes = fragments.size;
    std::sort(sizes.rbegin(), sizes.rend());
    if (sizes.size() > 10) sizes.resize(10);
    bodies.push_back(
        {{"name", b.name},
         {"dimension", b.dimension},
         {"points", b.size()},
         {"bonds", b.bond_count()},
         {"two_neighbour", b.total_two_neighbour()},
         {"three_neighbour", b.total_three_neighbour()},
         {"spacing", sb.spacing},
         {"horizon", b.horizon},
         // The constants in use: the analytic ones or, with `constants: calibrated`, those
         // solved from the lattice's patch test.
         {"constants", {{"c1", b.constants.c1}, {"c2", b.constants.c2}, {"c3", b.constants.c3}}},
         {"kernel", kernel_path_summary(b)},
         {"damage_rule", to_string(b.damage_rule)},
         {"force_form", to_string(b.force_form)},
         {"critical_stretch", b.damage_enabled ? nlohmann::ordered_json(b.critical_stretch)
                                               : nlohmann::ordered_json(nullptr)},
         {"precracked_bonds", sim.precracked_bonds(index)},
         {"broken_bonds", sim.broken_bonds(index)},
         {"max_damage", b.damage_enabled ? max_point_damage(b) : 0.0},
         {"beta", beta_summary(b)},
         {"inversion_penalty", b.inversion_penalty},
         {"inverted", sim.inverted(index)},
         // Each set once, over this process's force evaluations (Simulation::evaluated).
         {"evaluated",
          {{"bonds", sim.evaluated(index).bonds},
           {"triangles", sim.evaluated(index).triangles},
           {"tetrahedra", sim.evaluated(index).tetrahedra}}},
         // Connected components of intact bonds; single points count.
         {"fragments", fragments.count()},
         {"largest_fragments", sizes}});
    if (sb.rigid) {
      // The rigid motion at the end: every process moves a rigid body whole, so its own copy
      // (the whole scene's is the one it started from in a distributed run).
      const SceneBody& moved = sim.scene().bodies.size() == sim.whole_scene().bodies.size()
                                   ? sim.scene().bodies[index]
                                   : sb;
      const RigidMotion& r = *moved.rigid;
      const Vec3 c = r.centre(), v = r.velocity(), w = r.angular_velocity();
      nlohmann::ordered_json rigid = {{"motion", r.prescribed() ? "prescribed" : "free"},
                                      {"mass", r.mass()},
                                      {"centre", {c.x(), c.y(), c.z()}},
                                      {"velocity", {v.x(), v.y(), v.z()}},
                                      {"angular_velocity", {w.x(), w.y(), w.z()}}};
      if (sb.sphere_radius > 0) rigid["dem_sphere_radius"] = sb.sphere_radius;
      bodies.back()["rigid"] = rigid;
    }
    if (sb.far_field)
      bodies.back()["far_field"] = {{"tolerance", sb.far_field->tolerance},
                                    {"corotated", sb.far_field->corotated},
                                    {"exact_fraction", sb.far_field->exact_fraction()},
                                    {"operator_bytes", sb.far_field->op.bytes()},
                                    {"operator_row_classes", sb.far_field->op.classes},
                                    {"operator_rows_assembled", sb.far_field->op.assembled}};
  }
  j["points"] = points;
  j["bonds"] = bonds;
  j["two_neighbour"] = pairs;
  j["three_neighbour"] = triples;
  j["steps"] = sim.step();
  j["time"] = sim.time();
  const StepChoice& s = sim.step_choice();
  j["dt"] = s.dt;
  j["dt_estimate"] = s.estimate;
  j["dt_safety"] = s.safety;
  j["dt_limited_by"] = {{"body", s.limiting_body}, {"point", s.limiting_point}};
  // time.step_mode: fixed (dt throughout) or adaptive: the smallest step the current stable step
  // asked for (dt when none was lower) and how many steps were taken below dt.
  j["step_mode"] = sim.adaptive() ? "adaptive" : "fixed";
  if (sim.adaptive())
    j["adaptive_step"] = {
        {"smallest_step", std::min(s.dt, sim.smallest_step())},
        {"reduced_steps", sim.reduced_steps()},
        {"next_step", sim.step_size(sim.step() + 1)},
        {"current_stable_step", std::isfinite(sim.current_stable_step())
                                    ? nlohmann::ordered_json(sim.current_stable_step())
                                    : nlohmann::ordered_json(nullptr)},
        {"stable_step_seconds", sim.stable_step_seconds()}};
  // The contact speed bound (null without contact or motion) and whether dt was lowered to it.
  j["dt_contact_speed_bound"] = std::isfinite(s.speed_step)
                                    ? nlohmann::ordered_json{{"dt", s.speed_step},
                                                             {"closing_speed", s.closing_speed},
                                                             {"contact_radius", s.contact_radius},
                                                             {"bodies", s.speed_pair},
                                                             {"fraction", kContactStepFraction},
                                                             {"limits_dt", s.speed_limited}}
                                    : nlohmann::ordered_json(nullptr);
  j["wall_seconds"] = wall_seconds;
  j["peak_rss_mb"] = peak_rss_mb();
  j["max_damage"] = sim.max_damage();
  j["broken_bonds"] = sim.broken_bonds();
  const Energies e = sim.energies();
  j["energy"] = {{"kinetic", e.kinetic},
                 {"strain", e.strain},
                 {"contact", e.contact},
                 {"external_work", e.external_work},
                 {"dissipated", e.dissipated},
                 {"contact_damping", e.contact_damping},
                 {"contact_friction", e.contact_friction},
                 {"balance_error", e.balance_error}};
  j["inversion"] = inversion_summary(sim);
  j["bodies"] = bodies;
  j["contact"] = contact_summary(sim);
  return j;
}

void write_json(const std::string& path, const nlohmann::ordered_json& json) {
  write_file_replacing(path, json.dump(2) + '\n', "the summary");
}

}  // namespace ckpd
