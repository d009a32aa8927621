#include "src/cli/cli_options.hpp"

#include "ckpd_build_info.hpp"
#include "ckpd_git_commit.hpp"
#include "src/cli/isa.hpp"
#include "src/engine/ranks.hpp"

namespace ckpd {

CLI::Option* add_threads_option(CLI::App& cmd, int& threads, const std::string& name,
                                const std::string& help) {
  const CLI::Validator range(
      [name](std::string& text) -> std::string {
        std::size_t used = 0;
        long long n = 0;
        try {
          n = std::stoll(text, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used != text.size() || text.empty() || n < 1 || n > kMaxThreads)
          return "expected a whole number of threads from 1 to " + std::to_string(kMaxThreads) +
                 ", got '" + text + "'";
        return "";
      },
      "1.." + std::to_string(kMaxThreads));
  return cmd.add_option(name, threads, help)->check(range);
}

std::string instruction_set_text() {
  std::string extensions;
  for (const std::string& name : isa::compiled_extensions())
    extensions += (extensions.empty() ? "" : " ") + name;
  if (extensions.empty()) extensions = "baseline only";
  return std::string("CKPD_ARCH=") + build::kArch + " (" + build::kMarch +
         "), extensions: " + extensions + ", fp-contract " + build::kFpContract;
}

std::string version_line() {
  return std::string("ckpd ") + build::kVersion + " (commit " + build::kGitCommit + ", " +
         build::kBuildType + ", " + build::kCompiler + ", flags " + build::kFlags +
         "), instruction set " + instruction_set_text() + ", MPI " + ranks::mpi_text();
}

nlohmann::ordered_json build_json() {
  return {{"version", build::kVersion},
          {"commit", build::kGitCommit},
          {"build_type", build::kBuildType},
          {"compiler", build::kCompiler},
          {"flags", build::kFlags},
          {"arch", build::kArch},
          {"march", build::kMarch},
          {"isa_extensions", isa::compiled_extensions()},
          {"fp_contract", build::kFpContract},
          {"mpi", ranks::mpi_text()}};
}

namespace {
std::string& stored_command_line() {
  static std::string line;
  return line;
}
}  // namespace

void set_command_line(int argc, char** argv) {
  std::string& line = stored_command_line();
  line.clear();
  for (int k = 0; k < argc; ++k) {
    std::string word = argv[k];
    if (word.empty() || word.find_first_of(" \t'\"$\\*?;&|<>()") != std::string::npos) {
      std::string quoted = "'";
      for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
      word = quoted + "'";
    }
    line += (k ? " " : "") + word;
  }
}

const std::string& command_line() {
  return stored_command_line();
}

}  // namespace ckpd
