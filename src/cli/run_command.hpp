#pragma once
#include <CLI/CLI.hpp>

namespace ckpd {
// `ckpd run CASE [--out DIR] [--set key.path=value ...] [--threads N] [--quiet]`.
// Exit status: 0 completed, 2 bad input, 3 the run went unstable (history kept, summary says so).
void add_run_command(CLI::App& app, int& exit_status);
}  // namespace ckpd
