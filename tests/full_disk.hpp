#pragma once
// Running `ckpd` on a disk that fills up (tests/fault/full_disk.c, preloaded): writes to files
// under one folder fail with ENOSPC from a chosen write on.
#include <string>

#include "run_helpers.hpp"

namespace ckpd::testing {

// `ckpd args` with the disk under `folder` full from its `first_full`-th write there on (0: never
// full). With `count_file`, the number of writes there is left in it at exit.
inline CommandResult run_ckpd_on_full_disk(const std::filesystem::path& folder,
                                           long long first_full, const std::string& args,
                                           const std::filesystem::path& count_file = {}) {
  std::string env =
      std::string("LD_PRELOAD=") + CKPD_FULL_DISK + " CKPD_FULL_DISK_DIR=" + folder.string();
  if (first_full > 0) env += " CKPD_FULL_DISK_CALL=" + std::to_string(first_full);
  if (!count_file.empty()) env += " CKPD_FULL_DISK_COUNT=" + count_file.string();
  return run_ckpd_with(env, args);
}

}  // namespace ckpd::testing
