#include "src/output/progress.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>

namespace ckpd {

namespace {

std::size_t terminal_width() {
  winsize w{};
  if (ioctl(STDOUT_FILENO, TIOCGWINSZ, &w) == 0 && w.ws_col > 0) return w.ws_col;
  if (const char* columns = std::getenv("COLUMNS")) {
    const long c = std::strtol(columns, nullptr, 10);
    if (c > 0) return static_cast<std::size_t>(c);
  }
  return 80;
}

std::string printf_string(const char* format, double value) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, value);
  return buf;
}

}  // namespace

std::string format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "?";
  const auto s = static_cast<long long>(std::llround(seconds));
  char buf[32];
  if (s < 60)
    std::snprintf(buf, sizeof buf, "%lld s", s);
  else if (s < 3600)
    std::snprintf(buf, sizeof buf, "%lld:%02lld", s / 60, s % 60);
  else
    std::snprintf(buf, sizeof buf, "%lld:%02lld:%02lld", s / 3600, (s / 60) % 60, s % 60);
  return buf;
}

std::string format_progress(const ProgressState& p, std::size_t width) {
  const double percent =
      p.total > 0 ? 100.0 * static_cast<double>(p.step) / static_cast<double>(p.total) : 100.0;
  const double eta = p.rate > 0 ? static_cast<double>(p.total - p.step) / p.rate : std::nan("");
  // In order of importance: the line keeps as many as fit.
  std::vector<std::string> parts{printf_string("%5.1f%%", percent),
                                 "step " + std::to_string(p.step) + "/" + std::to_string(p.total),
                                 printf_string("t %.4g s", p.time),
                                 "elapsed " + format_duration(p.elapsed),
                                 "ETA " + format_duration(eta),
                                 printf_string("%.3g steps/s", p.rate),
                                 printf_string("damage %.3f", p.max_damage),
                                 p.energy_step < 0
                                     ? std::string("energy error: not yet evaluated")
                                     : printf_string("energy error %.2g%%", 100 * p.energy_error) +
                                           " (at step " + std::to_string(p.energy_step) + ")"};
  if (p.exact_fraction >= 0)
    parts.insert(parts.begin() + 7, printf_string("exact %.3f", p.exact_fraction));
  std::string line = parts[0];
  for (std::size_t k = 1; k < parts.size(); ++k) {
    if (line.size() + 2 + parts[k].size() > width) break;
    line += "  " + parts[k];
  }
  if (line.size() > width) line.resize(width);
  return line;
}

ProgressReporter::ProgressReporter(bool enabled, long long total_steps)
    : enabled_(enabled),
      terminal_(isatty(STDOUT_FILENO) != 0),
      total_(total_steps),
      start_(std::chrono::steady_clock::now()),
      last_(start_),
      last_log_(start_) {}

void ProgressReporter::energy_evaluated(const Simulation& sim) {
  const Energies e = sim.energies();
  const double scale = std::max({std::abs(e.external_work), e.kinetic + e.strain, 1e-300});
  energy_step_ = sim.step();
  energy_error_ = std::abs(e.balance_error) / scale;
}

ProgressState ProgressReporter::state(const Simulation& sim) const {
  ProgressState p;
  p.step = sim.step();
  p.total = sim.adaptive() ? sim.planned_steps() : total_;  // an adaptive step's estimate
  p.time = sim.time();
  p.elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  p.rate = p.elapsed > 0 ? static_cast<double>(sim.step() - start_step_) / p.elapsed : 0.0;
  p.max_damage = sim.max_damage();
  if (sim.has_far_field()) p.exact_fraction = sim.exact_fraction();
  p.energy_step = energy_step_;
  p.energy_error = energy_error_;
  return p;
}

void ProgressReporter::update(const Simulation& sim) {
  if (start_step_ < 0) start_step_ = sim.step() - 1;
  const auto now = std::chrono::steady_clock::now();
  const bool last = sim.step() >= (sim.adaptive() ? sim.planned_steps() : total_);
  const auto plain_every = std::chrono::seconds(10);
  if (log_ && (now - last_log_ >= plain_every || last)) {
    last_log_ = now;
    log_(format_progress(state(sim), 1000));
  }
  if (!enabled_) return;
  const auto every = terminal_ ? std::chrono::milliseconds(250) : plain_every;
  if (now - last_ < every && !last) return;
  last_ = now;
  if (terminal_) {
    // One column spare: a line exactly as wide as the terminal wraps on some terminals.
    const std::size_t width = std::max<std::size_t>(terminal_width(), 20) - 1;
    std::printf("\r%s\033[K", format_progress(state(sim), width).c_str());
  } else {
    std::printf("%s\n", format_progress(state(sim), 1000).c_str());
  }
  std::fflush(stdout);
  line_open_ = terminal_;
}

void ProgressReporter::finish() {
  if (line_open_) std::printf("\n");
  line_open_ = false;
}

}  // namespace ckpd
