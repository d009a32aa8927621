#include "src/sweep/shard_check.hpp"

#include <filesystem>
#include <fstream>

#include "src/sweep/sweep_file.hpp"

namespace ckpd::sweep {

namespace {

std::optional<nlohmann::json> parse_file(const std::string& path, std::string& problem) {
  std::ifstream in(path);
  if (!in) {
    problem = "cannot be read";
    return std::nullopt;
  }
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception&) {
    problem = "is not valid JSON";
    return std::nullopt;
  }
}

}  // namespace

ShardMeta read_shard_meta(const std::string& dir) {
  const std::string file = dir + "/sweep.json";
  std::string problem;
  const std::optional<nlohmann::json> j = parse_file(file, problem);
  if (!j)
    throw SweepError(file + ": " + problem + " (is " + dir + " the output folder of a sweep?)");
  if (!j->is_object())
    throw SweepError(file + ": expected an object (sweep_id, runs, ...), got " + j->dump());
  auto key = [&](const char* name, const char* expected) -> const nlohmann::json& {
    if (!j->contains(name))
      throw SweepError(file + ": missing key '" + name + "' (" + expected +
                       "; ckpd sweep writes it)");
    return j->at(name);
  };
  ShardMeta meta;
  meta.sweep_id = key("sweep_id", "the sweep's identity, a string");
  if (!meta.sweep_id.is_string() || meta.sweep_id.get<std::string>().empty())
    throw SweepError(file + ": sweep_id: expected the sweep's identity, a non-empty string, got " +
                     meta.sweep_id.dump());
  const std::string runs_expected =
      "a whole number of runs from 1 to " + std::to_string(kMaxRuns) + " (the most of a sweep)";
  const nlohmann::json& runs = key("runs", runs_expected.c_str());
  if (!runs.is_number_unsigned() || runs.get<std::uint64_t>() < 1 ||
      runs.get<std::uint64_t>() > static_cast<std::uint64_t>(kMaxRuns))
    throw SweepError(file + ": runs: expected " + runs_expected + ", got " + runs.dump());
  meta.runs = runs.get<std::size_t>();
  meta.sweep_file = key("sweep_file", "the sweep file's path");
  meta.base = key("base", "the base case's path");
  return meta;
}

std::string completed_run_problem(const std::string& folder, const std::string& hash) {
  if (!std::filesystem::is_directory(folder)) return "its folder " + folder + " is gone";
  std::string problem;
  const auto summary = parse_file(folder + "/summary.json", problem);
  if (!summary) return folder + "/summary.json " + problem;
  const nlohmann::json status =
      summary->is_object() ? summary->value("status", nlohmann::json()) : nlohmann::json();
  if (status != "completed")
    return folder + "/summary.json says status " + (status.is_null() ? "(none)" : status.dump());
  const auto record = parse_file(folder + "/sweep_run.json", problem);
  if (!record) return folder + "/sweep_run.json " + problem;
  const nlohmann::json own =
      record->is_object() ? record->value("hash", nlohmann::json()) : nlohmann::json();
  if (own != hash)
    return folder + "/sweep_run.json holds the run of hash " + own.dump() + ", not " + hash;
  return "";
}

}  // namespace ckpd::sweep
