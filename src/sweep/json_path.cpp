#include "src/sweep/json_path.hpp"

#include "src/input/case_node.hpp"
#include "src/sweep/generators.hpp"

namespace ckpd::sweep {

std::vector<std::string> split_json_path(const std::string& path) {
  std::vector<std::string> parts;
  std::string current;
  auto bad = [&](const std::string& why) {
    throw std::invalid_argument("metric path '" + path + "': " + why);
  };
  for (std::size_t i = 0; i < path.size(); ++i) {
    const char c = path[i];
    if (c == '.') {
      if (current.empty() && (parts.empty() || path[i - 1] != ']')) bad("an empty key");
      if (!current.empty()) parts.push_back(current);
      current.clear();
    } else if (c == '[') {
      if (!current.empty())
        parts.push_back(current);
      else if (parts.empty())
        bad("'[' must follow a key");
      current.clear();
      const std::size_t close = path.find(']', i);
      const std::string index = close == std::string::npos ? "" : path.substr(i + 1, close - i - 1);
      if (index.empty() || index.find_first_not_of("0123456789") != std::string::npos)
        bad("expected [index] with a non-negative integer");
      parts.push_back(index);
      i = close;
    } else {
      current += c;
    }
  }
  if (!current.empty())
    parts.push_back(current);
  else if (path.empty() || path.back() == '.')
    bad("an empty key");
  return parts;
}

std::optional<nlohmann::json> find_json(const nlohmann::json& root, const std::string& path,
                                        std::string& missing) {
  const nlohmann::json* node = &root;
  std::string walked;
  for (const std::string& key : split_json_path(path)) {
    walked += (walked.empty() ? "" : ".") + key;
    const nlohmann::json* next = nullptr;
    if (node->is_object()) {
      const auto it = node->find(key);
      if (it != node->end()) next = &*it;
    } else if (node->is_array()) {
      const std::optional<std::size_t> index = parse_index(key);
      if (index && *index < node->size()) {
        next = &(*node)[*index];
      } else {
        for (const auto& e : *node)
          if (e.is_object() && e.contains("name") && e["name"] == key) next = &e;
      }
    }
    if (!next) {
      missing = walked;
      return std::nullopt;
    }
    node = next;
  }
  return *node;
}

std::string json_cell(const nlohmann::json& value) {
  if (value.is_number_float()) return format_number(value.get<double>());
  if (value.is_string()) return value.get<std::string>();
  return value.dump();
}

}  // namespace ckpd::sweep
