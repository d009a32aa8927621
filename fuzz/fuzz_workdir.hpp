#pragma once
// A private scratch folder for a harness: the loaders read files, so each input is written to
// a file there. cases/ is mirrored into it (a copy, so that no input can change the sources):
// seeds that name meshes, point clouds or a sweep's base case by relative path still find them.
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace ckpd::fuzz {

inline const std::filesystem::path& workdir() {
  static const std::filesystem::path dir = [] {
    static char pattern[] = "/tmp/ckpd_fuzz_XXXXXX";  // static: read by the exit handler
    const char* made = mkdtemp(pattern);
    if (!made) std::abort();
    std::filesystem::copy(std::string(CKPD_SOURCE_DIR) + "/cases", made,
                          std::filesystem::copy_options::recursive);
    // Removed at exit: libFuzzer's fork mode starts a process per job, and a 30-minute run
    // left 262 copies (210 MB) in /tmp. (Not through `dir`: it is destroyed before the
    // handler runs, having been constructed after the handler was registered.)
    std::atexit([] {
      std::error_code ignored;
      std::filesystem::remove_all(pattern, ignored);
    });
    return std::filesystem::path(made);
  }();
  return dir;
}

// Writes the input to `name` under the scratch folder and returns the path.
inline std::string write_input(const std::string& name, const std::uint8_t* data,
                               std::size_t size) {
  const std::filesystem::path path = workdir() / name;
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path.string();
}

}  // namespace ckpd::fuzz
