#pragma once
// Helpers for tests that go through case files and the `ckpd` program: write a case into a
// fresh temporary folder, run the binary, read what it wrote.
#include <sys/wait.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <string>

namespace ckpd::testing {

// A new empty folder under the system temp directory.
inline std::filesystem::path fresh_dir(const std::string& tag) {
  static std::mt19937_64 rng(std::random_device{}());
  auto dir = std::filesystem::temp_directory_path() /
             ("ckpd-test-" + tag + "-" + std::to_string(rng() % 1000000000));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

inline std::string write_file(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path) << text;
  return path.string();
}

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

// A shell command (stdout and stderr together).
inline CommandResult run_ckpd_command(const std::string& command) {
  CommandResult r;
  const std::string cmd = command + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return r;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, pipe)) r.output += buf;
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

inline CommandResult run_ckpd(const std::string& args) {
  return run_ckpd_command(std::string(CKPD_BINARY) + " " + args);
}

// `ckpd args` with environment assignments (`env`: "NAME=value ...", or empty) before it.
inline CommandResult run_ckpd_with(const std::string& env, const std::string& args) {
  return run_ckpd_command(env + (env.empty() ? "" : " ") + CKPD_BINARY + " " + args);
}

// run_ckpd under coreutils' `timeout`: a command that hangs is killed after `limit_seconds`
// (exit status 137); `seconds` is the wall time it took.
struct TimedResult : CommandResult {
  double seconds = 0;
};
inline TimedResult run_ckpd_within(int limit_seconds, const std::string& args) {
  const auto start = std::chrono::steady_clock::now();
  TimedResult r;
  static_cast<CommandResult&>(r) =
      run_ckpd_command("timeout -s KILL " + std::to_string(limit_seconds) + " " +
                       std::string(CKPD_BINARY) + " " + args);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

inline std::string file_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

inline nlohmann::json read_json(const std::filesystem::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

}  // namespace ckpd::testing
