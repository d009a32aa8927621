#include "src/output/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>

namespace ckpd {

ProgressReporter::ProgressReporter(bool enabled, long long total_steps)
    : enabled_(enabled),
      terminal_(isatty(STDOUT_FILENO) != 0),
      total_(total_steps),
      start_(std::chrono::steady_clock::now()),
      last_(start_) {}

void ProgressReporter::update(const Simulation& sim) {
  if (!enabled_) return;
  if (start_step_ < 0) start_step_ = sim.step() - 1;
  const auto now = std::chrono::steady_clock::now();
  const auto every = terminal_ ? std::chrono::milliseconds(250) : std::chrono::milliseconds(10000);
  if (now - last_ < every && sim.step() < total_) return;
  last_ = now;
  print(sim);
}

void ProgressReporter::print(const Simulation& sim) {
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double rate = elapsed > 0 ? static_cast<double>(sim.step() - start_step_) / elapsed : 0.0;
  const double eta = rate > 0 ? static_cast<double>(total_ - sim.step()) / rate : 0.0;
  const Energies e = sim.energies();
  const double scale = std::max({std::abs(e.external_work), e.kinetic + e.strain, 1e-300});
  std::printf(
      "%sstep %lld/%lld  t = %.4g s  %.3g steps/s  ETA %.0f s  max damage %.3f  "
      "energy error %.2g%%%s",
      terminal_ ? "\r" : "", sim.step(), total_, sim.time(), rate, eta, sim.max_damage(),
      100 * std::abs(e.balance_error) / scale, terminal_ ? "\033[K" : "\n");
  std::fflush(stdout);
  line_open_ = terminal_;
}

void ProgressReporter::finish() {
  if (line_open_) std::printf("\n");
  line_open_ = false;
}

}  // namespace ckpd
