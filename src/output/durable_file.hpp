#pragma once
// Files replaced only when their new version is complete: a writer writes PATH.partial, which is
// synced to the disk and then renamed over PATH (and the folder synced), so PATH is at every
// moment either its previous version or the new one, whole, even when the disk fills up or the
// process is killed. A write that fails removes the temporary and throws OutputError; PATH is
// left as it was.
#include <cstddef>
#include <stdexcept>
#include <string>

namespace ckpd {

// An output file that could not be written; the previous version of the file is unchanged.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The temporary name a file is written under before it replaces `path`.
std::string partial_path(const std::string& path);

// Syncs `temp` (complete and closed) to the disk (where a full disk may show only now) and
// renames it over `path`; on failure removes `temp` and throws OutputError naming `path` and
// `what` ("the checkpoint"). `sync_folder`: the rename made durable too (false: a later
// replace_file in the same folder does it, one sync for several files).
void replace_file(const std::string& temp, const std::string& path, const std::string& what,
                  bool sync_folder = true);

// Writes `text` as the new version of `path` (through partial_path(path), replace_file).
void write_file_replacing(const std::string& path, const std::string& text, const std::string& what,
                          bool sync_folder = true);

// An open file that is appended to, each append whole or not at all: an append that fails is cut
// off again (the file keeps its previous length) and throws OutputError. Appends are synced.
class AppendFile {
 public:
  AppendFile() = default;
  // Opens `path` for appending (created empty when absent).
  AppendFile(const std::string& path, const std::string& what);
  ~AppendFile();
  AppendFile(AppendFile&& other) noexcept;
  AppendFile& operator=(AppendFile&& other) noexcept;
  AppendFile(const AppendFile&) = delete;
  AppendFile& operator=(const AppendFile&) = delete;
  void append(const std::string& text);
  // Syncs what was appended to the disk.
  void sync();

 private:
  int fd_ = -1;
  std::string path_, what_;
};

// "" when `path` is free for a file (absent, or a file), else a message that says what is in the
// way (a folder, a device).
std::string blocked_path(const std::string& path);

}  // namespace ckpd
