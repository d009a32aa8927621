// A disk that fills up, for tests (LD_PRELOAD=libckpd_full_disk.so): the write calls of a
// process to files under CKPD_FULL_DISK_DIR are counted, and from the CKPD_FULL_DISK_CALL-th one
// (counted from 1) on the disk is full: that call writes half of its bytes (at least none, at
// most all but one) and fails with ENOSPC, as write(2) does when the space runs out in the
// middle of a buffer, and every later write to such a file fails with ENOSPC at once. Writes to
// other files (the terminal, pipes, files elsewhere) pass untouched. Without CKPD_FULL_DISK_CALL
// nothing fails and the count is only kept: at exit it is written to the file
// CKPD_FULL_DISK_COUNT, when that is set (a test learns how many failure points a run has).
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/uio.h>
#include <unistd.h>

static long long calls;  // write calls to files under the directory so far

static int under_directory(int fd) {
  const char* dir = getenv("CKPD_FULL_DISK_DIR");
  if (!dir || !*dir) return 0;
  char link[64], target[PATH_MAX];
  snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
  const ssize_t n = readlink(link, target, sizeof target - 1);
  if (n <= 0) return 0;
  target[n] = '\0';
  const size_t len = strlen(dir);
  return strncmp(target, dir, len) == 0 && (target[len] == '/' || target[len] == '\0');
}

// How many of `size` bytes this call may write (SIZE_MAX: all, the disk has room).
static size_t allowed(int fd, size_t size) {
  if (!under_directory(fd)) return (size_t)-1;
  const long long call = ++calls;
  const char* limit = getenv("CKPD_FULL_DISK_CALL");
  if (!limit || !*limit) return (size_t)-1;
  const long long first_full = atoll(limit);
  if (call < first_full) return (size_t)-1;
  if (call == first_full && size > 1) return size / 2;
  return 0;
}

static void* next(const char* name) {
  return dlsym(RTLD_NEXT, name);
}

#define FULL_DISK_FAIL \
  do {                 \
    errno = ENOSPC;    \
    return -1;         \
  } while (0)

ssize_t write(int fd, const void* buf, size_t size) {
  static ssize_t (*real)(int, const void*, size_t);
  if (!real) real = (ssize_t(*)(int, const void*, size_t))next("write");
  const size_t room = allowed(fd, size);
  if (room == 0) FULL_DISK_FAIL;
  if (room < size) {
    const ssize_t done = real(fd, buf, room);
    if (done >= 0) FULL_DISK_FAIL;
    return done;
  }
  return real(fd, buf, size);
}

static ssize_t positioned(ssize_t (*real)(int, const void*, size_t, off_t), int fd, const void* buf,
                          size_t size, off_t offset) {
  const size_t room = allowed(fd, size);
  if (room == 0) FULL_DISK_FAIL;
  if (room < size) {
    const ssize_t done = real(fd, buf, room, offset);
    if (done >= 0) FULL_DISK_FAIL;
    return done;
  }
  return real(fd, buf, size, offset);
}

ssize_t pwrite(int fd, const void* buf, size_t size, off_t offset) {
  static ssize_t (*real)(int, const void*, size_t, off_t);
  if (!real) real = (ssize_t(*)(int, const void*, size_t, off_t))next("pwrite");
  return positioned(real, fd, buf, size, offset);
}

ssize_t pwrite64(int fd, const void* buf, size_t size, off_t offset) {
  static ssize_t (*real)(int, const void*, size_t, off_t);
  if (!real) real = (ssize_t(*)(int, const void*, size_t, off_t))next("pwrite64");
  return positioned(real, fd, buf, size, offset);
}

// Vector writes (libstdc++'s file streams use writev): all or nothing per call.
ssize_t writev(int fd, const struct iovec* iov, int count) {
  static ssize_t (*real)(int, const struct iovec*, int);
  if (!real) real = (ssize_t(*)(int, const struct iovec*, int))next("writev");
  if (allowed(fd, 0) != (size_t)-1) FULL_DISK_FAIL;
  return real(fd, iov, count);
}

ssize_t pwritev(int fd, const struct iovec* iov, int count, off_t offset) {
  static ssize_t (*real)(int, const struct iovec*, int, off_t);
  if (!real) real = (ssize_t(*)(int, const struct iovec*, int, off_t))next("pwritev");
  if (allowed(fd, 0) != (size_t)-1) FULL_DISK_FAIL;
  return real(fd, iov, count, offset);
}

__attribute__((destructor)) static void report_count(void) {
  const char* path = getenv("CKPD_FULL_DISK_COUNT");
  if (!path || !*path) return;
  FILE* f = fopen(path, "w");
  if (!f) return;
  fprintf(f, "%lld\n", calls);
  fclose(f);
}
