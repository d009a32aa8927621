#include "src/input/case_node.hpp"

#include <yaml-cpp/depthguard.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <sstream>

#include "src/input/key_table.hpp"
#include "src/input/nearest_name.hpp"
#include "src/input/yaml_document.hpp"

namespace ckpd {

namespace {

std::string child_path(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

bool valid_utf8(const std::string& text) {
  std::size_t i = 0;
  while (i < text.size()) {
    const auto c = static_cast<unsigned char>(text[i]);
    std::size_t extra = 0;
    std::uint32_t code = 0;
    if (c < 0x80) {
      ++i;
      continue;
    } else if ((c & 0xE0) == 0xC0) {
      extra = 1, code = c & 0x1F;
    } else if ((c & 0xF0) == 0xE0) {
      extra = 2, code = c & 0x0F;
    } else if ((c & 0xF8) == 0xF0) {
      extra = 3, code = c & 0x07;
    } else {
      return false;
    }
    if (i + extra >= text.size()) return false;
    for (std::size_t k = 1; k <= extra; ++k) {
      const auto d = static_cast<unsigned char>(text[i + k]);
      if ((d & 0xC0) != 0x80) return false;
      code = (code << 6) | (d & 0x3F);
    }
    // Overlong forms, surrogates and values past U+10FFFF are not UTF-8.
    static constexpr std::uint32_t kMin[4] = {0, 0x80, 0x800, 0x10000};
    if (code < kMin[extra] || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return false;
    i += extra + 1;
  }
  return true;
}

std::string line_of(const std::string& file, const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  return mark.line >= 0 ? file + ":" + std::to_string(mark.line + 1) : file;
}

std::string node_text(const YAML::Node& node) {
  if (node.IsScalar()) return "'" + node.Scalar() + "'";
  if (node.IsSequence()) return "a list";
  if (node.IsMap()) return "a map";
  return "nothing";
}

// The section of a map: `s`, or its alternative when the map holds the alternative's key.
const KeySection* resolve(const KeySection* s, const YAML::Node& node) {
  if (!s || s->alternative_key.empty() || !node.IsMap() || !node[s->alternative_key]) return s;
  const KeySection* alternative = find_key_section(s->alternative);
  if (!alternative)
    throw std::logic_error("key section '" + s->name + "' names alternative '" + s->alternative +
                           "', which is not registered");
  return alternative;
}

// The variant a map of section `s` is (its discriminator's value, or the default), kept in
// `store`; null when the section has no variants or the value names none.
const std::string* variant_of(const KeySection& s, const YAML::Node& node, std::string& store) {
  if (s.discriminator.empty() || !node.IsMap()) return nullptr;
  const YAML::Node d = node[s.discriminator];
  if (d && d.IsScalar())
    store = d.Scalar();
  else if (!d && !s.default_variant.empty())
    store = s.default_variant;
  else
    return nullptr;
  return s.find_variant(store) ? &store : nullptr;
}

}  // namespace

CaseNode::CaseNode(YAML::Node node, std::string file, std::string path)
    : node_(std::move(node)),
      file_(std::move(file)),
      path_(std::move(path)),
      used_(std::make_shared<std::set<std::string>>()) {}

void CaseNode::set_overrides(std::vector<Override> overrides) {
  overrides_ = std::make_shared<const std::vector<Override>>(std::move(overrides));
  for (const Override& o : *overrides_)
    if (o.value.is(node_)) override_ = o.text;
}

void CaseNode::set_key_section(const KeySection* section) {
  section_ = resolve(section, node_);
}

const KeySpec* CaseNode::declared(const std::string& key) const {
  if (!section_) return nullptr;
  std::string store;
  if (const KeySpec* k = section_->find(key, variant_of(*section_, node_, store))) return k;
  if (const KeySpec* k = section_->find(key)) return k;  // another variant's, read to refuse it
  if (key == section_->alternative_key) return nullptr;  // asks whether the map is the other kind
  if (const KeySection* other = find_key_section(section_->refuses_keys_of))
    if (other->find(key)) return nullptr;
  throw std::logic_error("the loader reads key '" + key + "' of " +
                         (path_.empty() ? std::string("the top level") : path_) +
                         ", which key section '" + section_->name +
                         "' does not declare (src/input/key_table.hpp)");
}

void CaseNode::describe(CaseNode& c, const KeySpec* spec) const {
  if (!spec || spec->ref.empty()) return;
  const KeySection* ref = find_key_section(spec->ref);
  if (!ref)
    throw std::logic_error("key '" + spec->name + "' names key section '" + spec->ref +
                           "', which is not registered");
  if (spec->kind == ValueKind::sections || spec->kind == ValueKind::named_sections)
    c.items_ = ref;
  else
    c.section_ = resolve(ref, c.node_);
}

std::vector<std::string> CaseNode::known_keys(bool present_unread) const {
  if (!section_) return {used_->begin(), used_->end()};
  // The table's keys for this map's variant (the keys of other variants and sections that the
  // loader reads only to refuse them are none of them).
  std::set<std::string> known;
  std::string store;
  for (const std::string& k : section_->key_names(variant_of(*section_, node_, store)))
    if (!present_unread || used_->count(k) || !node_.IsMap() || !node_[k]) known.insert(k);
  return {known.begin(), known.end()};
}

CaseNode CaseNode::child(YAML::Node node, std::string path) const {
  CaseNode c(std::move(node), file_, std::move(path));
  c.overrides_ = overrides_;
  c.override_ = override_;
  if (overrides_ && c.override_.empty())
    for (const Override& o : *overrides_)
      if (o.value.is(c.node_)) c.override_ = o.text;
  return c;
}

std::string CaseNode::key_where(const YAML::Node& key, const std::string& name) const {
  const std::string path = child_path(path_, name);
  if (overrides_)
    for (const Override& o : *overrides_)
      if (o.value.is(node_[name])) return "--set " + o.text + ": " + path;
  if (!override_.empty()) return "--set " + override_ + ": " + path;
  // A case built in memory (a Python dict) has no lines: the key path says where.
  if (key.Mark().line < 0) return file_ + ": " + path;
  return file_ + ":" + std::to_string(key.Mark().line + 1) + ": " + path;
}

std::string CaseNode::misspelt_key_error() const {
  if (!node_.IsMap()) return "";
  const std::vector<std::string> known = known_keys(false);
  for (const auto& kv : node_) {
    const std::string key = kv.first.as<std::string>();
    // A key of the table not read yet is no misspelling.
    if (used_->count(key) || (section_ && section_->find(key))) continue;
    const std::string near = nearest_name(key, known);
    if (!near.empty())
      return key_where(kv.first, key) + ": unknown key '" + key + "' (did you mean '" + near +
             "'?)";
  }
  return "";
}

std::string CaseNode::where() const {
  if (!override_.empty()) return "--set " + override_ + ": " + (path_.empty() ? "" : path_);
  std::ostringstream s;
  s << file_;
  const YAML::Mark mark = node_.Mark();
  if (mark.line >= 0) s << ":" << mark.line + 1;
  s << ": " << (path_.empty() ? "(top level)" : path_);
  return s.str();
}

void CaseNode::fail(const std::string& expected) const {
  // "expected an end time or a number of steps" is about a map whose key is misspelt: say so.
  if (const std::string misspelt = misspelt_key_error(); !misspelt.empty())
    throw CaseError(misspelt);
  throw CaseError(where() + ": expected " + expected + ", got " + node_text(node_));
}

bool CaseNode::has(const std::string& key) const {
  declared(key);
  return node_.IsMap() && node_[key];
}

std::optional<CaseNode> CaseNode::optional(const std::string& key) const {
  if (!node_.IsMap()) fail("a map");
  const KeySpec* spec = declared(key);
  used_->insert(key);
  const YAML::Node child = node_[key];
  if (!child || child.IsNull()) return std::nullopt;
  CaseNode c = this->child(child, child_path(path_, key));
  describe(c, spec);
  return c;
}

CaseNode CaseNode::required(const std::string& key) const {
  if (!node_.IsMap()) fail("a map with key '" + key + "'");
  auto child = optional(key);
  if (!child) {
    // A misspelt key is the likely cause: name it with the key it should be.
    for (const auto& kv : node_) {
      const std::string name = kv.first.as<std::string>();
      if (!used_->count(name) && nearest_name(name, {key}) == key)
        throw CaseError(key_where(kv.first, name) + ": unknown key '" + name + "' (did you mean '" +
                        key + "'?)");
    }
    throw CaseError(where() + ": missing required key '" + key + "'");
  }
  return *child;
}

std::vector<CaseNode> CaseNode::elements() const {
  if (!node_.IsSequence()) fail("a list");
  std::vector<CaseNode> out;
  for (std::size_t i = 0; i < node_.size(); ++i) {
    out.push_back(child(node_[i], path_ + "[" + std::to_string(i) + "]"));
    out.back().section_ = resolve(items_, out.back().node_);
  }
  return out;
}

std::vector<std::pair<std::string, CaseNode>> CaseNode::entries() const {
  if (!node_.IsMap()) fail("a map");
  std::vector<std::pair<std::string, CaseNode>> out;
  for (const auto& kv : node_) {
    const std::string key = kv.first.as<std::string>();
    // Every key counts as read: the input's keys, not the loader's, so none is a logic error.
    const KeySpec* spec = section_ ? section_->find(key) : nullptr;
    used_->insert(key);
    out.emplace_back(key, child(kv.second, child_path(path_, key)));
    describe(out.back().second, spec);
    if (items_) out.back().second.section_ = resolve(items_, out.back().second.node_);
  }
  return out;
}

double CaseNode::as_double() const {
  if (!node_.IsScalar()) fail("a number");
  const std::string& text = node_.Scalar();
  std::size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    fail("a number");
  }
  if (used != text.size() || !std::isfinite(value)) fail("a finite number");
  if (std::abs(value) > kMaxMagnitude) fail("a number of magnitude at most 1e30");
  return value;
}

double CaseNode::as_in_range(double lo, double hi, const std::string& what) const {
  const double v = as_double();
  if (!(v >= lo && v <= hi)) {
    std::ostringstream s;
    if (lo > 0 && !(v > 0)) s << "a positive number: ";
    s << what << " from " << lo << " to " << hi;
    fail(s.str());
  }
  return v;
}

double CaseNode::as_positive() const {
  const double v = as_double();
  if (!(v > 0)) fail("a positive number");
  return v;
}

double CaseNode::as_non_negative() const {
  const double v = as_double();
  if (!(v >= 0)) fail("a non-negative number");
  return v;
}

long long CaseNode::as_integer() const {
  const double v = as_double();
  if (v != std::floor(v) || std::abs(v) > 9e15) fail("an integer");
  return static_cast<long long>(v);
}

bool CaseNode::as_bool() const {
  if (!node_.IsScalar()) fail("true or false");
  const std::string& t = node_.Scalar();
  if (t == "true" || t == "yes" || t == "on") return true;
  if (t == "false" || t == "no" || t == "off") return false;
  fail("true or false");
}

std::string CaseNode::as_string() const {
  if (!node_.IsScalar()) fail("a string");
  return node_.Scalar();
}

std::vector<double> CaseNode::as_doubles() const {
  std::vector<double> out;
  for (const CaseNode& e : elements()) out.push_back(e.as_double());
  return out;
}

Vec3 CaseNode::as_vector(int dimension) const {
  if (!node_.IsSequence() || static_cast<int>(node_.size()) != dimension)
    fail("a list of " + std::to_string(dimension) + " numbers (the body's dimension)");
  const std::vector<double> v = as_doubles();
  return Vec3(v[0], v[1], dimension == 3 ? v[2] : 0.0);
}

Vec3 CaseNode::as_vector_below(int dimension, double limit, const std::string& what) const {
  const Vec3 v = as_vector(dimension);
  if (!(v.norm() < limit)) {
    std::ostringstream s;
    s << what << " of magnitude below " << limit << " (got " << v.norm() << ")";
    fail(s.str());
  }
  return v;
}

void CaseNode::finish() const {
  if (!node_.IsMap()) return;
  for (const auto& kv : node_) {
    const std::string key = kv.first.as<std::string>();
    if (!used_->count(key)) {
      std::ostringstream s;
      s << key_where(kv.first, key) << ": unknown key '" << key << "'";
      const std::vector<std::string> known = known_keys(true);
      if (const std::string near = nearest_name(key, known); !near.empty())
        s << " (did you mean '" << near << "'?)";
      else if (!known.empty())
        s << " (expected one of: " << join_names(known) << ")";
      throw CaseError(s.str());
    }
  }
}

void check_yaml_document(const YAML::Node& root, const std::string& file) {
  // Iterative: a deeply nested document must not exhaust the stack here.
  std::vector<std::pair<YAML::Node, std::string>> pending{{root, ""}};
  while (!pending.empty()) {
    const auto [node, path] = pending.back();
    pending.pop_back();
    if (node.IsScalar() && !valid_utf8(node.Scalar()))
      throw CaseError(line_of(file, node) + ": " + (path.empty() ? "(top level)" : path) +
                      ": the text is not valid UTF-8");
    if (node.IsSequence()) {
      for (std::size_t i = 0; i < node.size(); ++i)
        pending.emplace_back(node[i], path + "[" + std::to_string(i) + "]");
    } else if (node.IsMap()) {
      std::set<std::string> seen;
      for (const auto& kv : node) {
        if (!kv.first.IsScalar())
          throw CaseError(line_of(file, kv.first) + ": " + (path.empty() ? "(top level)" : path) +
                          ": a key must be a plain name, not " + node_text(kv.first));
        const std::string key = kv.first.Scalar();
        if (!valid_utf8(key))
          throw CaseError(line_of(file, kv.first) + ": " + (path.empty() ? "(top level)" : path) +
                          ": a key that is not valid UTF-8");
        if (!seen.insert(key).second)
          throw CaseError(line_of(file, kv.first) + ": " + child_path(path, key) + ": key '" + key +
                          "' given twice in the same map (the first value would win)");
        pending.emplace_back(kv.second, child_path(path, key));
      }
    }
  }
}

YAML::Node load_case_yaml(const std::string& file, const std::vector<std::string>& overrides,
                          std::vector<CaseNode::Override>* applied) {
  YAML::Node root = load_yaml_file(file, "case file");
  if (!root.IsMap())
    throw CaseError(file + ": a case file is a map of sections (materials, bodies, ...)");
  apply_overrides(root, overrides, file, applied);
  return root;
}

std::optional<std::size_t> parse_index(const std::string& text) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos) return {};
  std::size_t value = 0;
  for (const char c : text) {
    const std::size_t digit = static_cast<std::size_t>(c - '0');
    if (value > (std::numeric_limits<std::size_t>::max() - digit) / 10) return {};
    value = value * 10 + digit;
  }
  return value;
}

void apply_overrides(YAML::Node& root, const std::vector<std::string>& overrides,
                     const std::string& file, std::vector<CaseNode::Override>* applied) {
  for (const std::string& item : overrides) {
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0)
      throw CaseError("--set " + item + ": expected key.path=value");
    const std::string path = item.substr(0, eq), text = item.substr(eq + 1);
    YAML::Node value;
    try {
      value = YAML::Load(text);
    } catch (const YAML::Exception& e) {
      throw CaseError("--set " + item + ": the value is not valid YAML: " + e.msg);
    }
    std::istringstream events(text);  // an alias inside itself, an alias bomb: refused
    check_yaml_events(events, "--set " + item, "value");
    std::vector<std::string> keys;
    std::stringstream ss(path);
    for (std::string k; std::getline(ss, k, '.');) keys.push_back(k);
    // yaml-cpp nodes are handles: walking with copies and assigning through them edits `root`.
    YAML::Node node = root;
    std::string walked;
    for (std::size_t n = 0; n < keys.size(); ++n) {
      const std::string& key = keys[n];
      const bool last = n + 1 == keys.size();
      YAML::Node next;
      if (node.IsSequence()) {
        bool found = false;
        const std::optional<std::size_t> index = parse_index(key);
        for (std::size_t e = 0; e < node.size() && !found; ++e) {
          if ((index && *index == e) ||
              (node[e].IsMap() && node[e]["name"] && node[e]["name"].Scalar() == key)) {
            next.reset(node[e]);
            found = true;
          }
        }
        if (!found)
          throw CaseError("--set " + path + ": '" + walked + "' has no element '" + key + "'");
      } else if (node.IsMap()) {
        if (!node[key] && !last)
          throw CaseError("--set " + path + ": '" + (walked.empty() ? key : walked + "." + key) +
                          "' does not exist in " + file);
        if (last) {
          node[key] = value;
          if (applied) applied->push_back({item, node[key]});
          break;
        }
        next.reset(node[key]);
      } else {
        throw CaseError("--set " + path + ": '" + walked + "' is a value, not a map or a list");
      }
      if (last) {
        next = value;
        if (applied) applied->push_back({item, next});
        break;
      }
      node.reset(next);
      walked = walked.empty() ? key : walked + "." + key;
    }
  }
}

}  // namespace ckpd
