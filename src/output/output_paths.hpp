#pragma once
// The files a run writes in its output folder, checked before its first step: a folder (or
// anything but a file) where one of them must go would otherwise be found only when that file
// is written, after every step had run.
#include <string>
#include <vector>

namespace ckpd {

// "" when every path the run may write in `out` is free for a file, else a message naming the
// first that is not. `bodies`: the bodies' names (each has its XDMF series with field output).
std::string blocked_output(const std::string& out, const std::vector<std::string>& bodies,
                           bool fields);

// Removes DIR/fields.xdmf and every body's series DIR/fields_*.xdmf.
void remove_field_indexes(const std::string& out);

// Removes what a run that failed before its first step wrote in `out` (its log, history, frames
// and indexes): nothing it left may pass for a run's output.
void remove_started_output(const std::string& out);

}  // namespace ckpd
