#pragma once
#include <CLI/CLI.hpp>

namespace ckpd {
// `ckpd patch-test`: N1..N3 of an interior point and the energy ratios as JSON.
void add_patch_test_command(CLI::App& app);
}  // namespace ckpd
