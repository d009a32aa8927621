#pragma once
#include <CLI/CLI.hpp>

#include "bodies/body.hpp"

namespace ckpd {
// MB the body's own arrays hold (state, per-point constants, family, adjacency rows); the
// report's "of body data" (also the Python module's check_case).
double body_megabytes(const Body& b);

// `ckpd check CASE [--set ...] [--steps N] [--threads N]`: validates a case without running
// it and reports what a run would cost. Its timed steps exit 3 on instability, as `run` does.
void add_check_command(CLI::App& app, int& exit_status);
}  // namespace ckpd
