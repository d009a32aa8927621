#pragma once
// A checked view of a YAML case file. Every read names the file, the key path and the line in
// its error; every map remembers which keys were read, so that `finish()` rejects the ones that
// were not (a typo must never pass silently).
#include <yaml-cpp/yaml.h>

#include <memory>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "bodies/vec.hpp"

namespace ckpd {

struct KeySection;  // src/input/key_table.hpp
struct KeySpec;

// Bad input in a case file: the message names file, line, key path and what was expected.
class CaseError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class CaseNode {
 public:
  CaseNode(YAML::Node node, std::string file, std::string path = "");

  // Map access. `required` throws when the key is missing; `optional` returns nullopt.
  CaseNode required(const std::string& key) const;
  std::optional<CaseNode> optional(const std::string& key) const;
  bool has(const std::string& key) const;
  // Sequence access.
  std::vector<CaseNode> elements() const;
  // All entries of a map, in file order (each key counts as read).
  std::vector<std::pair<std::string, CaseNode>> entries() const;

  bool is_map() const { return node_.IsMap(); }
  bool is_sequence() const { return node_.IsSequence(); }
  bool is_scalar() const { return node_.IsScalar(); }

  // Every number is finite and of magnitude at most kMaxMagnitude: SI values of any physical
  // case are far inside, and products of a few such numbers (volumes, energies) stay finite.
  static constexpr double kMaxMagnitude = 1e30;
  double as_double() const;
  // A number in [lo, hi]; `what` says what it is ("a Young's modulus in Pa").
  double as_in_range(double lo, double hi, const std::string& what) const;
  double as_positive() const;      // > 0 and finite
  double as_non_negative() const;  // >= 0 and finite
  long long as_integer() const;
  bool as_bool() const;
  std::string as_string() const;
  // A list of `dimension` numbers; in 2D the z component is 0.
  Vec3 as_vector(int dimension) const;
  // A vector whose length is below `limit`; `what` names it ("a velocity in m/s").
  Vec3 as_vector_below(int dimension, double limit, const std::string& what) const;
  // Speeds (m/s) are below the speed of light: an initial velocity of 1e300 gave null energies.
  static constexpr double kMaxSpeed = 2.99792458e8;
  std::vector<double> as_doubles() const;

  // Throws for every key of this map that was never read.
  void finish() const;

  [[noreturn]] void fail(const std::string& expected) const;
  const std::string& path() const { return path_; }
  const std::string& file() const { return file_; }
  const YAML::Node& yaml() const { return node_; }  // the raw node, e.g. to re-emit it
  // "file:line: path", or "--set key.path=value: path" for a value an override put there.
  std::string where() const;

  // The values `--set` put into the tree (from load_case_yaml): errors about them, and about
  // anything inside them, name the override instead of a line of the file.
  struct Override {
    std::string text;  // "key.path=value" as given
    YAML::Node value;
  };
  void set_overrides(std::vector<Override> overrides);

  // Binds this map to a section of the key table (src/input/key_table.hpp): it and the maps
  // below it then read only keys their sections declare (another read throws std::logic_error:
  // the loader and the table disagree), and unknown keys are named against the table.
  void set_key_section(const KeySection* section);
  const KeySection* key_section() const { return section_; }

 private:
  CaseNode child(YAML::Node node, std::string path) const;
  // An unread key of this map that looks like a misspelling of a read one: the error for it
  // (with the nearest known key), or "".
  std::string misspelt_key_error() const;
  std::string key_where(const YAML::Node& key, const std::string& name) const;
  // The table's entry for `key` of this map (null when the map is bound to no section); throws
  // std::logic_error for a key the section does not declare.
  const KeySpec* declared(const std::string& key) const;
  // Binds a child to the section(s) its key's entry names.
  void describe(CaseNode& child, const KeySpec* spec) const;
  // The keys a key of this map may be: the section's for this map's variant (with
  // `present_unread`, less the ones given but never read: those are not accepted here), or the
  // keys read so far when the map is bound to no section.
  std::vector<std::string> known_keys(bool present_unread) const;

  YAML::Node node_;
  std::string file_;
  std::string path_;
  std::shared_ptr<std::set<std::string>> used_;
  std::shared_ptr<const std::vector<Override>> overrides_;
  std::string override_;  // the --set text this node came from; "" when from the file
  const KeySection* section_ = nullptr;  // the keys of this map
  const KeySection* items_ = nullptr;    // the keys of this list's (or named map's) maps
};

// A list index written as a key (`bodies.0.spacing`): the number when `text` is decimal digits
// only and fits in size_t, else nothing (no exception, however long the digits run).
std::optional<std::size_t> parse_index(const std::string& text);

// Throws CaseError (file:line) for a key given twice in one map, a key that is not a plain
// scalar (`? [a, b]`) and a scalar that is not valid UTF-8: yaml-cpp accepts all three, and the
// first value of a duplicated key would silently win.
void check_yaml_document(const YAML::Node& root, const std::string& file);

// Loads a case file (throws CaseError for a missing file or a YAML syntax error, with the line)
// and applies `--set key.path=value` overrides: each path must lead through existing maps and
// sequences (a sequence element by index or by its `name`); the last key may be new.
// `applied`, when given, receives each override with the node it put into the tree.
YAML::Node load_case_yaml(const std::string& file, const std::vector<std::string>& overrides,
                          std::vector<CaseNode::Override>* applied = nullptr);
// The overrides alone, on a case already in memory (`file` names it in the errors).
void apply_overrides(YAML::Node& root, const std::vector<std::string>& overrides,
                     const std::string& file, std::vector<CaseNode::Override>* applied = nullptr);

}  // namespace ckpd
