#pragma once
// Reads a YAML case file into a Scene: materials, bodies sampled from geometry primitives,
// pre-cracks, no-failure zones, conditions, time and output settings. Every error is a
// CaseError that names the file, the line, the key and what was expected.
#include <string>
#include <vector>

#include "src/engine/scene.hpp"

namespace ckpd {

// `overrides` are `key.path=value` strings (the command line's --set).
Scene load_scene(const std::string& case_file, const std::vector<std::string>& overrides = {});
// A case already in memory (overrides applied), e.g. built from a Python dict: `case_file` names
// it in the errors and the summary; relative mesh paths are resolved against its directory
// (the working directory for a name without one, such as "case dict").
Scene load_scene(YAML::Node resolved, const std::string& case_file,
                 std::vector<CaseNode::Override> applied = {});

}  // namespace ckpd
