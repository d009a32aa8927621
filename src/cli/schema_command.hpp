#pragma once
#include <CLI/CLI.hpp>

namespace ckpd {
// `ckpd schema [--markdown]`: prints the JSON Schema (draft 2020-12) of the case file, or with
// --markdown the case-file reference (docs/CASE_FILE.md), both from the loader's key table.
void add_schema_command(CLI::App& app);
}  // namespace ckpd
