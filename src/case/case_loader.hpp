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

}  // namespace ckpd
