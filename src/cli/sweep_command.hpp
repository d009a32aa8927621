#pragma once
#include <CLI/CLI.hpp>

namespace ckpd {
// `ckpd sweep SWEEP [--jobs N] [--threads-per-run T] [--out DIR] [--shard I/N] [--dry-run]
// [--quiet]` and `ckpd sweep-merge DIR... --out DIR`. Exit status: 0 every run completed, 2 bad
// input (nothing run), 4 some runs failed (or, for merge, are not completed), 130 interrupted.
void add_sweep_command(CLI::App& app, int& exit_status);
}  // namespace ckpd
