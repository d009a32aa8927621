#include "src/output/run_driver.hpp"

#include <omp.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "src/engine/ranks.hpp"
#include "src/output/checkpoint.hpp"
#include "src/output/history_quantities.hpp"
#include "src/output/output_paths.hpp"
#include "src/output/output_share.hpp"

namespace ckpd {

RunDriver::RunDriver(Simulation& sim, RunDriverOptions options)
    : sim_(sim),
      options_(std::move(options)),
      resume_(options_.restarted_from.empty() ? -1 : sim.step()),
      total_(sim.planned_steps()),
      progress_(options_.progress, sim.planned_steps()),
      writes_(!options_.out.empty() && ranks::root()),
      shared_(!options_.out.empty() && shared_output(sim)),
      row_gathers_(history_needs_whole_scene(sim.scene().output.history)) {
  const OutputSettings& o = sim_.scene().output;
  interval_ = o.history_interval > 0 ? o.history_interval : std::max<long long>(1, total_ / 200);
  std::string failure;
  if (writes_) {
    const std::string& out = options_.out;
    bool started = false;  // this constructor wrote into the folder
    try {
      std::error_code ec;
      std::filesystem::create_directories(out, ec);
      if (ec || !std::filesystem::is_directory(out))
        throw std::runtime_error(out + ": cannot create the output directory");
      std::vector<std::string> bodies;
      for (const SceneBody& sb : sim_.whole_scene().bodies) bodies.push_back(sb.body.name);
      if (const std::string why = blocked_output(out, bodies, o.writes_fields()); !why.empty())
        throw std::runtime_error(why);
      // Summaries of earlier runs in this folder must not pass for this one's.
      std::filesystem::remove(out + "/summary.json", ec);
      started = true;
      log_.emplace(out + "/run.log", resume_ >= 0);
      for (const std::string& line : options_.log_header) log_->write(line);
      if (resume_ >= 0)
        log_->write("restarted from " + options_.restarted_from + " at step " +
                    std::to_string(resume_));
      progress_.set_log([this](const std::string& line) { log_->write(line); });
      history_.emplace(out + "/history.csv", resume_, o.history, sim_.has_far_field(), interval_);
      if (o.writes_fields()) fields_.emplace(out, o.fields, resume_);
    } catch (const std::runtime_error& e) {
      failure = e.what();
      if (started) abandon_output();
    }
  }
  // Only rank 0 writes: the other ranks learn of its failure here, before the gather below would
  // wait for it (the caller prints rank 0's message once).
  if (ranks::any(!failure.empty()))
    throw std::runtime_error(failure.empty() ? "rank 0 could not prepare the output" : failure);
  // Every rank knows whether there is a history (its rows' quantities are sums over the ranks).
  has_history_ = ranks::from_root(history_.has_value());
  // Every rank counts the frames, so that all know when one is due; with shared files the other
  // ranks write their points into them.
  const long long kept =
      ranks::from_root(fields_ ? static_cast<long long>(fields_->frames()) : -1LL);
  if (!ranks::root() && kept >= 0)
    fields_.emplace(FieldWriter::follower(options_.out, o.fields, static_cast<std::size_t>(kept)));
  // A distributed run: rank 0's whole scene holds every rank's state for the first row (with
  // fragments) and frame (when rank 0 writes it alone).
  if ((has_history_ && row_gathers_) || (fields_ && !shared_)) gather();
  try {
    if (resume_ < 0 && has_history_) write_row();
    if (resume_ < 0) row_step_ = sim_.step();
    if (fields_ && (resume_ < 0 || fields_->frames() == 0)) write_frame();
  } catch (const std::runtime_error&) {
    // Only rank 0 can fail here (in a shared file a failure ends every rank): the caller's
    // agreement on the set-up tells the others.
    if (writes_) abandon_output();
    throw;
  }
  progress_.energy_evaluated(sim_);
  // Model breakdown (inverted tetrahedra/triangles) is reported once, when first seen.
  report_inversion();
}

void RunDriver::abandon_output() {
  // A new run that could not start leaves nothing that passes for its output; a restart's files
  // are replaced only whole, so the run it continues keeps its own.
  progress_.set_log({});
  log_.reset();
  history_.reset();
  fields_.reset();
  if (resume_ < 0) remove_started_output(options_.out);
}

double RunDriver::seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - options_.start).count();
}

// Frame k is written at the first step whose time reaches k * field_time_interval.
bool RunDriver::frame_due(long long step, double time) const {
  if (!fields_) return false;
  const OutputSettings& o = sim_.scene().output;
  if (o.field_interval > 0) return step % o.field_interval == 0;
  return time >= static_cast<double>(fields_->frames()) * o.field_time_interval -
                     1e-9 * sim_.step_choice().dt;
}

void RunDriver::gather() {
  if (gathered_step_ == sim_.step()) return;
  sim_.gather_whole();
  gathered_step_ = sim_.step();
}

void RunDriver::report_inversion() {
  if (inversion_reported_ || sim_.first_inversion().step < 0) return;
  inversion_reported_ = true;
  progress_.finish();
  std::cerr << "ckpd: warning: " << inversion_warning(sim_) << '\n';
  log("warning: " + inversion_warning(sim_));
}

void RunDriver::log(const std::string& line) {
  if (log_) log_->write(line);
}

void RunDriver::step(bool with_energy) {
  if (finished()) throw std::logic_error("RunDriver::step: the run has reached its last step");
  const long long next = sim_.step() + 1;
  const bool last = next == total_steps();
  const bool row = next % interval_ == 0 || last;
  const double dt = sim_.step_choice().dt;
  // An adaptive step's time is its own sum of steps (the time after the next step).
  const double next_time = sim_.adaptive() ? sim_.next_time() : static_cast<double>(next) * dt;
  const bool frame = frame_due(next, next_time) || (fields_ && last);
  // Only rank 0 has the output (an MPI run): every rank evaluates the energy when it does.
  const bool energy = ranks::from_root(with_energy || row || (frame && fields_->needs_energy()));
  sim_.advance(energy);
  if (energy) progress_.energy_evaluated(sim_);
  const long long every = sim_.scene().output.checkpoint_interval;
  const bool checkpoint = every > 0 && sim_.step() % every == 0;
  // Every rank knows what is due: in a distributed run all take part in the gather. A row needs
  // it only for the case's own history quantities (the default columns are the books, summed over
  // ranks every step), frames and checkpoints in shared files never.
  if ((row && row_gathers_) || ((frame || checkpoint) && !shared_)) gather();
  if (row) {
    if (has_history_) write_row();
    row_step_ = sim_.step();
  }
  report_inversion();
  if (frame) write_frame();
  progress_.update(sim_);
  if (checkpoint) write_checkpoint();
}

void RunDriver::write_row() {
  // The chosen quantities: a collective on distributed memory; on replicated state rank 0's own.
  const auto& chosen = sim_.scene().output.history;
  std::vector<double> values;
  if (!chosen.empty() && (sim_.distribution() || history_)) values = history_values(sim_, chosen);
  if (history_) history_->write_row(sim_, values);
}

void RunDriver::write_frame() {
  // A frame in a shared file takes every rank; otherwise rank 0 writes it and the others count it.
  if (writes_ || shared_)
    fields_->write_frame(sim_);
  else
    fields_->count_frame();
}

void RunDriver::write_checkpoint() {
  // On every rank: the gather of a distributed run, or with shared files the write, is a
  // collective; otherwise rank 0 writes. The history's rows so far reach the disk with it.
  if (checkpoint_step_ == sim_.step()) return;
  checkpoint_step_ = sim_.step();
  if (history_) history_->sync();
  if (shared_) {
    ckpd::write_checkpoint(checkpoint_path(), sim_);
    return;
  }
  gather();
  if (writes_) ckpd::write_checkpoint(checkpoint_path(), sim_);
}

nlohmann::ordered_json RunDriver::summary(const std::string& status,
                                          const std::string& message) const {
  auto j = make_summary(sim_, status, message, seconds());
  j["setup_seconds"] = options_.setup_seconds;
  const long long stepped = sim_.step() - std::max(resume_, 0LL);  // by this process
  j["seconds_per_step"] =
      stepped > 0 ? (seconds() - options_.setup_seconds) / static_cast<double>(stepped) : 0.0;
  j["threads"] = omp_get_max_threads();
  j["ranks"] = ranks::count();
  if (!options_.decomposition.is_null()) j["decomposition"] = options_.decomposition;
  if (fields_) j["field_frames"] = fields_->frames();
  if (!options_.restarted_from.empty())
    j["restarted_from"] = {{"file", options_.restarted_from}, {"step", resume_}};
  if (!options_.provenance.is_null()) j["provenance"] = options_.provenance;
  return j;
}

void RunDriver::stop(const std::string& status, const std::string& message) {
  progress_.finish();
  // The last step had no evaluation with energy: the row and the summary must not carry the
  // strain energy of the row before against this step's kinetic energy and work.
  const bool refresh = row_step_ != sim_.step() && ranks::from_root(history_.has_value());
  if (refresh) sim_.refresh_strain_energy();  // a collective in an MPI run
  // The last row's and the summary's bodies, gathered again: a step that threw may have moved
  // them without counting, and a refresh gives new strain energy densities.
  gathered_step_ = -1;
  gather();
  if (refresh && has_history_) write_row();
  row_step_ = sim_.step();
  if (status == "completed") {
    std::ostringstream line;
    line << "completed " << sim_.step() << " steps to t = " << sim_.time() << " s in " << seconds()
         << " s; peak RSS " << peak_rss_mb() << " MB; max damage " << sim_.max_damage()
         << "; results in " << options_.out;
    log(line.str());
  } else {
    log("stopped (" + status + "): " + message);
  }
  // The summary last: the run's files are complete when it is there.
  if (writes_) write_json(options_.out + "/summary.json", summary(status, message));
}

}  // namespace ckpd
