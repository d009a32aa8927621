#include "src/output/run_log.hpp"

#include <ctime>
#include <sstream>

namespace ckpd {

namespace {

AppendFile open_log(const std::string& path, bool append) {
  // A new run's log replaces the previous run's whole.
  if (!append) write_file_replacing(path, "", "the run log");
  return AppendFile(path, "the run log");
}

}  // namespace

RunLog::RunLog(const std::string& path, bool append) : out_(open_log(path, append)) {}

void RunLog::write(const std::string& text) {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%SZ", &utc);
  std::istringstream lines(text);
  std::string stamped;
  for (std::string line; std::getline(lines, line);) stamped += stamp + ("  " + line) + '\n';
  out_.append(stamped);
}

}  // namespace ckpd
