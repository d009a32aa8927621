#pragma once
// SIGINT/SIGTERM while a case is being set up (loading, sampling, building families: minutes
// for a large case). Nothing has been written yet, so the process stops at once with a message
// and exit status 130 instead of dying silently with 143 or running on to the first step.
// The handler only calls write(2) and _exit(2), which are async-signal-safe.
namespace ckpd {

// Installs the set-up handler for SIGINT and SIGTERM; the run replaces it with its own
// (finish the step, write a checkpoint) once the set-up is done.
void stop_on_signal_during_setup();

}  // namespace ckpd
