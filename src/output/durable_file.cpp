#include "src/output/durable_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace ckpd {

namespace {

// 0, or the errno of the write that failed.
int write_all(int fd, const char* data, std::size_t size) {
  while (size > 0) {
    const ssize_t done = ::write(fd, data, size);
    if (done < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    data += done;
    size -= static_cast<std::size_t>(done);
  }
  return 0;
}

[[noreturn]] void failed(const std::string& path, const std::string& what, int error,
                         const std::string& previous) {
  throw OutputError(path + ": cannot write " + what + " (" + std::strerror(error) + "); " +
                    previous);
}

std::string kept_note(const std::string& path) {
  return std::filesystem::exists(path) ? "its previous version is unchanged"
                                       : "nothing was written there";
}

// The folder a path is in ("." for a bare name).
std::string folder_of(const std::string& path) {
  const std::string parent = std::filesystem::path(path).parent_path().string();
  return parent.empty() ? "." : parent;
}

}  // namespace

std::string partial_path(const std::string& path) {
  return path + ".partial";
}

void replace_file(const std::string& temp, const std::string& path, const std::string& what,
                  bool sync_folder) {
  int error = 0;
  const int fd = ::open(temp.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    error = errno;
  } else {
    if (::fsync(fd) != 0) error = errno;
    ::close(fd);
  }
  if (error == 0 && std::rename(temp.c_str(), path.c_str()) != 0) error = errno;
  if (error != 0) {
    std::remove(temp.c_str());
    failed(path, what, error, kept_note(path));
  }
  if (!sync_folder) return;
  // The rename made durable (best effort: some file systems cannot sync a folder).
  const int dir = ::open(folder_of(path).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir >= 0) {
    ::fsync(dir);
    ::close(dir);
  }
}

void write_file_replacing(const std::string& path, const std::string& text, const std::string& what,
                          bool sync_folder) {
  const std::string temp = partial_path(path);
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) failed(path, what, errno, kept_note(path));
  int error = write_all(fd, text.data(), text.size());
  if (error == 0 && ::fsync(fd) != 0) error = errno;
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error != 0) {
    std::remove(temp.c_str());
    failed(path, what, error, kept_note(path));
  }
  replace_file(temp, path, what, sync_folder);
}

AppendFile::AppendFile(const std::string& path, const std::string& what)
    : fd_(::open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644)),
      path_(path),
      what_(what) {
  if (fd_ < 0) failed(path, what, errno, kept_note(path));
}

AppendFile::~AppendFile() {
  if (fd_ >= 0) ::close(fd_);
}

AppendFile::AppendFile(AppendFile&& other) noexcept
    : fd_(other.fd_), path_(std::move(other.path_)), what_(std::move(other.what_)) {
  other.fd_ = -1;
}

AppendFile& AppendFile::operator=(AppendFile&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = other.fd_;
    path_ = std::move(other.path_);
    what_ = std::move(other.what_);
    other.fd_ = -1;
  }
  return *this;
}

void AppendFile::append(const std::string& text) {
  const off_t length = ::lseek(fd_, 0, SEEK_END);
  const int error = length < 0 ? errno : write_all(fd_, text.data(), text.size());
  if (error == 0) return;
  // Whatever part of `text` reached the file is cut off again.
  if (length >= 0 && ::ftruncate(fd_, length) == 0)
    failed(path_, what_, error, "it keeps what it held before");
  failed(path_, what_, error, "its last line may be cut off");
}

void AppendFile::sync() {
  if (fd_ >= 0 && ::fdatasync(fd_) != 0) failed(path_, what_, errno, "it may not be on the disk");
}

std::string blocked_path(const std::string& path) {
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0 || S_ISREG(info.st_mode)) return "";
  return path + ": " + (S_ISDIR(info.st_mode) ? "a folder" : "something other than a file") +
         " is where ckpd writes a file (remove or rename it)";
}

}  // namespace ckpd
