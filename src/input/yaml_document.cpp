#include "src/input/yaml_document.hpp"

#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/eventhandler.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <unordered_map>
#include <vector>

#include "src/input/case_node.hpp"

namespace ckpd {

namespace {

std::string at_line(const std::string& name, const YAML::Mark& mark) {
  return mark.line >= 0 ? name + ":" + std::to_string(mark.line + 1) : name;
}

// Counts the values of the document as a walk over the built tree would meet them: an alias
// counts as the whole node it names. A node's anchor is registered before its contents are
// parsed, so an alias to a list or map that is still open is an alias inside itself.
class Counter : public YAML::EventHandler {
 public:
  explicit Counter(std::string name) : name_(std::move(name)) {}

  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t anchor) override { leaf(mark, anchor); }
  void OnScalar(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                const std::string&) override {
    leaf(mark, anchor);
  }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t anchor) override {
    for (const Open& o : open_)
      if (o.anchor == anchor)
        throw CaseError(at_line(name_, mark) +
                        ": an alias inside the node its anchor names (a list or map that "
                        "contains itself); repeat the values instead");
    const auto it = size_.find(anchor);
    add(mark, it == size_.end() ? 1 : it->second);
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                       YAML::EmitterStyle::value) override {
    start(mark, anchor);
  }
  void OnSequenceEnd() override { end(); }
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                  YAML::EmitterStyle::value) override {
    start(mark, anchor);
  }
  void OnMapEnd() override { end(); }

 private:
  struct Open {
    YAML::anchor_t anchor;
    std::uint64_t count_before;
  };

  void add(const YAML::Mark& mark, std::uint64_t values) {
    count_ += values;  // values <= kMaxYamlValues + 1 each time: no overflow
    if (count_ > kMaxYamlValues)
      throw CaseError(at_line(name_, mark) + ": the document holds more than " +
                      std::to_string(kMaxYamlValues) +
                      " values (numbers, names, lists and maps, an alias counting as what it "
                      "repeats); a case describes a scene in far fewer");
  }
  void leaf(const YAML::Mark& mark, YAML::anchor_t anchor) {
    add(mark, 1);
    if (anchor != YAML::NullAnchor) size_[anchor] = 1;
  }
  void start(const YAML::Mark& mark, YAML::anchor_t anchor) {
    open_.push_back({anchor, count_});
    add(mark, 1);
  }
  void end() {
    const Open o = open_.back();
    open_.pop_back();
    if (o.anchor != YAML::NullAnchor) size_[o.anchor] = count_ - o.count_before;
  }

  std::string name_;
  std::uint64_t count_ = 0;
  std::vector<Open> open_;
  std::unordered_map<YAML::anchor_t, std::uint64_t> size_;
};

// yaml-cpp's exceptions as CaseError, with the line.
template <typename Read>
auto translated(const std::string& name, const std::string& what, Read read) {
  try {
    return read();
  } catch (const YAML::DeepRecursion& e) {
    throw CaseError(at_line(name, e.mark) + ": nested deeper than " + std::to_string(e.depth()) +
                    " levels (a " + what + " nests a few)");
  } catch (const YAML::ParserException& e) {
    throw CaseError(at_line(name, e.mark) + ": YAML syntax error: " + e.msg);
  } catch (const YAML::BadFile&) {
    throw CaseError(name + ": cannot read the " + what);
  } catch (const YAML::Exception& e) {
    throw CaseError(name + ": cannot read the " + what + ": " + e.what());
  }
}

}  // namespace

void check_yaml_events(std::istream& in, const std::string& name, const std::string& what) {
  translated(name, what, [&] {
    YAML::Parser parser(in);
    Counter counter(name);
    parser.HandleNextDocument(counter);  // yaml-cpp's Load reads the first document only
    return 0;
  });
}

YAML::Node load_yaml_file(const std::string& file, const std::string& what) {
  if (!std::filesystem::is_regular_file(file))
    throw CaseError(file + ": " + what + " not found (or not a regular file)");
  {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw CaseError(file + ": cannot read the " + what);
    check_yaml_events(in, file, what);
  }
  const YAML::Node root = translated(file, what, [&] { return YAML::LoadFile(file); });
  check_yaml_document(root, file);
  return root;
}

}  // namespace ckpd
