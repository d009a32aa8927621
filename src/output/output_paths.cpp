#include "src/output/output_paths.hpp"

#include <filesystem>

#include "src/output/durable_file.hpp"
#include "src/output/xdmf_index.hpp"

namespace ckpd {

namespace {

// A file and the temporary it is written under.
std::string blocked_file(const std::string& path) {
  std::string why = blocked_path(path);
  return why.empty() ? blocked_path(partial_path(path)) : why;
}

}  // namespace

std::string blocked_output(const std::string& out, const std::vector<std::string>& bodies,
                           bool fields) {
  std::vector<std::string> files = {"run.log", "history.csv", "summary.json", "checkpoint.h5"};
  if (fields) {
    files.push_back("fields.xdmf");
    for (const std::string& name : body_xdmf_names(bodies)) files.push_back(name);
  }
  for (const std::string& file : files)
    if (std::string why = blocked_file(out + "/" + file); !why.empty()) return why;
  if (!fields) return "";
  const std::string frames = out + "/fields";
  std::error_code ec;
  if (std::filesystem::exists(frames, ec) && !std::filesystem::is_directory(frames, ec))
    return frames +
           ": something other than a folder is where ckpd writes the field frames "
           "(remove or rename it)";
  if (!std::filesystem::is_directory(frames, ec)) return "";
  // The frames' names: frame_NNNNNN.h5 and their temporaries.
  for (const auto& entry : std::filesystem::directory_iterator(frames, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("frame_", 0) != 0) continue;
    if (std::string why = blocked_path(entry.path().string()); !why.empty()) return why;
  }
  return "";
}

void remove_field_indexes(const std::string& out) {
  std::error_code ec;
  std::filesystem::remove(out + "/fields.xdmf", ec);
  for (const auto& entry : std::filesystem::directory_iterator(out, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("fields_", 0) == 0 && entry.path().extension() == ".xdmf")
      std::filesystem::remove(entry.path(), ec);
  }
}

void remove_started_output(const std::string& out) {
  std::error_code ec;
  for (const char* file : {"run.log", "history.csv"}) std::filesystem::remove(out + "/" + file, ec);
  remove_field_indexes(out);
  const std::string frames = out + "/fields";
  for (const auto& entry : std::filesystem::directory_iterator(frames, ec))
    if (entry.path().filename().string().rfind("frame_", 0) == 0 && entry.is_regular_file(ec))
      std::filesystem::remove(entry.path(), ec);
  std::filesystem::remove(frames, ec);  // only when empty
}

}  // namespace ckpd
