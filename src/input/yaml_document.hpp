#pragma once
// Reading a YAML document (a case file, a sweep file, a `--set` value) within bounds. yaml-cpp
// follows an alias wherever it is used: `x: &x [*x]` is a list that contains itself (every walk
// over it runs for ever), nine lists of nine aliases to the list before expand to 9^10 values,
// and a few megabytes of numbers take hundreds of megabytes as yaml-cpp nodes. Before yaml-cpp
// builds the tree, one pass over the document's events refuses each of these with the line.
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <istream>
#include <string>

namespace ckpd {

// The most values (numbers, names, lists and maps, each alias counted as what it stands for) a
// document may hold: a case of a thousand bodies holds a few tens of thousands.
constexpr std::uint64_t kMaxYamlValues = 200'000;

// Throws CaseError ("NAME:LINE: ...") for an alias inside the node it names (a cycle), for a
// document that holds (or whose aliases expand to) more than kMaxYamlValues values, for nesting
// deeper than yaml-cpp's depth guard, and for a YAML syntax error. `name` is the file, or where
// the text came from ("--set time.end=..."); `what` the kind of document ("case file").
void check_yaml_events(std::istream& in, const std::string& name, const std::string& what);

// A document file read after check_yaml_events and check_yaml_document (case_node.hpp):
// every refusal a CaseError naming `file` and the line. `what` is the kind of file ("case
// file", "sweep file") for the error about a file that cannot be read.
YAML::Node load_yaml_file(const std::string& file, const std::string& what);

}  // namespace ckpd
