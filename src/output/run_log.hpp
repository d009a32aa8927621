#pragma once
// DIR/run.log: what a run printed and more, each line with its wall-clock time: the set-up
// lines, warnings, a progress line every 10 s and the final line. Written per line, so a killed
// run's log ends where the run did; a line that cannot be written (a full disk) is cut off again
// and throws OutputError (durable_file.hpp). A restart appends to the log of the run it continues.
#include <string>

#include "src/output/durable_file.hpp"

namespace ckpd {

class RunLog {
 public:
  // Throws std::runtime_error naming the path when it cannot be written.
  RunLog(const std::string& path, bool append);
  // Each line of `text` (a trailing newline is optional) as its own time-stamped line.
  void write(const std::string& text);

 private:
  AppendFile out_;
};

}  // namespace ckpd
