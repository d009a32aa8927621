#pragma once
#include <CLI/CLI.hpp>

namespace ckpd {
// `ckpd check CASE [--set ...] [--steps N] [--threads N]`: validates a case without running
// it and reports what a run would cost. Its timed steps exit 3 on instability, as `run` does.
void add_check_command(CLI::App& app, int& exit_status);
}  // namespace ckpd
