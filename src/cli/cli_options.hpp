#pragma once
// Options and error handling shared by the `ckpd` subcommands.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <string>

namespace ckpd {

// The most threads --threads accepts: far above any machine ckpd runs on, low enough that a
// slip (an extra digit) is an error instead of oversubscribing the machine.
inline constexpr int kMaxThreads = 4096;

// `--threads N`, N in 1..kMaxThreads (default 0 = OpenMP's choice).
CLI::Option* add_threads_option(CLI::App& cmd, int& threads, const std::string& name = "--threads",
                                const std::string& help = "OpenMP threads (default: all cores)");

// "CKPD_ARCH=A (M), extensions: E..., fp-contract C": the instruction set the binary was built
// for (the CKPD_ARCH option, what -march resolved to, the extensions the compiler was told to use).
std::string instruction_set_text();
// "ckpd VERSION (commit C, BUILD_TYPE, COMPILER, flags F), instruction set " and
// instruction_set_text(); one line (the run log's header starts it with the time).
std::string version_line();
// {"version", "commit", "build_type", "compiler", "flags", "arch", "march", "isa_extensions",
// "fp_contract"} for summary.json.
nlohmann::ordered_json build_json();

// The program's command line, as main() received it (words joined by spaces, each quoted when
// it holds a space or a shell character), for summary.json and the run log.
void set_command_line(int argc, char** argv);
const std::string& command_line();

}  // namespace ckpd
