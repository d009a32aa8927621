#include "src/output/run_log.hpp"

#include <ctime>
#include <sstream>
#include <stdexcept>

namespace ckpd {

RunLog::RunLog(const std::string& path, bool append)
    : out_(path, append ? std::ios::app : std::ios::trunc), path_(path) {
  if (!out_) throw std::runtime_error(path + ": cannot write the run log");
}

void RunLog::write(const std::string& text) {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%SZ", &utc);
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) out_ << stamp << "  " << line << '\n';
  out_.flush();
}

}  // namespace ckpd
