#pragma once
// Cases from Python: a path or a dict with the case file's schema. A dict becomes a YAML node
// tree without line marks, so the case loader's errors name its key paths ("bodies[0].spacing")
// where a file's would add the line. Overrides are `--set`'s: "key.path=value" strings or a
// dict {"key.path": value}.
#include <pybind11/pybind11.h>
#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "src/input/case_node.hpp"

namespace ckpd::python {

// What a case was given as, resolved: the YAML tree with the overrides applied, and the name
// its errors and summary.json use (the file, or "case dict").
struct ResolvedCase {
  YAML::Node root;
  std::string name;
  std::vector<CaseNode::Override> applied;  // the overrides, for errors that name them
};

// `source`: str or os.PathLike (a case file) or dict. Throws CaseError.
ResolvedCase resolve_case(const pybind11::handle& source, const pybind11::handle& overrides);

// The deepest nesting of dicts and lists a case dict may have (a case nests a few levels).
inline constexpr std::size_t kMaxDictDepth = 500;

// A Python value (dict, list, tuple, str, bool, int, float, None, numpy scalars and arrays) as
// a YAML node; `path` names it in the CaseError for anything else, for a container that
// contains itself (directly or further down) and for nesting deeper than kMaxDictDepth.
YAML::Node to_yaml(const pybind11::handle& value, const std::string& path);

// `overrides` (None, a dict or a list of "key=value" strings) as `--set` strings.
std::vector<std::string> override_strings(const pybind11::handle& overrides);

}  // namespace ckpd::python
