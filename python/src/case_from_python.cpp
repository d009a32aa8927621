#include "python/src/case_from_python.hpp"

#include <cmath>
#include <sstream>

#include "src/input/case_node.hpp"

namespace py = pybind11;

namespace ckpd::python {

namespace {

// Shortest text that reads back as the same double (Python's repr), in YAML's spelling of the
// non-finite values.
std::string number_text(double x) {
  if (std::isnan(x)) return ".nan";
  if (std::isinf(x)) return x > 0 ? ".inf" : "-.inf";
  return py::repr(py::float_(x)).cast<std::string>();
}

std::string child(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

std::string place(const std::string& path) {
  return path.empty() ? "(top level)" : path;
}

// The containers (dicts, lists, tuples, numpy values) between the top level and the value
// being converted, with their paths: a value met again on its own path is a cycle.
struct Ancestors {
  std::vector<std::pair<const PyObject*, std::string>> path;

  // Enters `value` at `where`; throws CaseError for a cycle or a nesting deeper than kMaxDepth.
  void enter(const py::handle& value, const std::string& where) {
    for (const auto& [object, at] : path)
      if (object == value.ptr())
        throw CaseError("case dict: " + place(where) + ": the value of " + place(at) +
                        " again, which contains it (a cycle; a case is a tree of dicts and "
                        "lists)");
    if (path.size() >= kMaxDictDepth)
      throw CaseError("case dict: " + place(where) + ": nested deeper than " +
                      std::to_string(kMaxDictDepth) + " levels (a case nests a few)");
    path.emplace_back(value.ptr(), where);
  }
};

YAML::Node convert(const py::handle& value, const std::string& path, Ancestors& above) {
  if (value.is_none()) return YAML::Node(YAML::NodeType::Null);
  if (py::isinstance<py::bool_>(value)) return YAML::Node(value.cast<bool>() ? "true" : "false");
  if (py::isinstance<py::str>(value)) return YAML::Node(value.cast<std::string>());
  if (py::isinstance<py::int_>(value)) return YAML::Node(py::str(value).cast<std::string>());
  if (py::isinstance<py::float_>(value)) return YAML::Node(number_text(value.cast<double>()));
  const bool dict = py::isinstance<py::dict>(value);
  const bool sequence = py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value);
  // numpy arrays and scalars: an array is not a list, a numpy bool is not a bool.
  const bool numpy =
      !dict && !sequence && py::hasattr(value, "tolist") && py::hasattr(value, "dtype");
  if (!dict && !sequence && !numpy)
    throw CaseError("case dict: " + place(path) +
                    ": expected a dict, list, string, number, bool or None, got " +
                    py::repr(py::type::of(value)).cast<std::string>());
  above.enter(value, path);
  struct Leave {
    Ancestors& a;
    ~Leave() { a.path.pop_back(); }
  } leave{above};
  if (numpy) return convert(value.attr("tolist")(), path, above);
  if (dict) {
    YAML::Node map(YAML::NodeType::Map);
    for (const auto& [k, v] : value.cast<py::dict>()) {
      if (!py::isinstance<py::str>(k))
        throw CaseError("case dict: " + place(path) + ": keys are strings, got " +
                        py::repr(k).cast<std::string>());
      const std::string key = k.cast<std::string>();
      map[key] = convert(v, child(path, key), above);
    }
    return map;
  }
  YAML::Node seq(YAML::NodeType::Sequence);
  std::size_t i = 0;
  for (const py::handle& e : value)
    seq.push_back(convert(e, path + "[" + std::to_string(i++) + "]", above));
  return seq;
}

}  // namespace

YAML::Node to_yaml(const py::handle& value, const std::string& path) {
  Ancestors above;
  return convert(value, path, above);
}

std::vector<std::string> override_strings(const py::handle& overrides) {
  std::vector<std::string> out;
  if (overrides.is_none()) return out;
  if (py::isinstance<py::dict>(overrides)) {
    for (const auto& [k, v] : overrides.cast<py::dict>()) {
      const std::string key = py::str(k).cast<std::string>();
      YAML::Emitter text;
      text << YAML::Flow << to_yaml(v, key);
      out.push_back(key + "=" + text.c_str());
    }
    return out;
  }
  if (py::isinstance<py::str>(overrides))
    throw CaseError(
        "overrides: expected a dict or a list of 'key.path=value' strings, got a string");
  for (const py::handle& item : overrides) out.push_back(py::str(item).cast<std::string>());
  return out;
}

ResolvedCase resolve_case(const py::handle& source, const py::handle& overrides) {
  const std::vector<std::string> sets = override_strings(overrides);
  if (py::isinstance<py::dict>(source)) {
    ResolvedCase c{to_yaml(source, ""), "case dict", {}};
    apply_overrides(c.root, sets, c.name, &c.applied);
    return c;
  }
  const py::module_ os = py::module_::import("os");
  if (!py::isinstance<py::str>(source) && !py::hasattr(source, "__fspath__"))
    throw CaseError("case: expected a case file (str or path) or a dict, got " +
                    py::repr(py::type::of(source)).cast<std::string>());
  const std::string file = os.attr("fspath")(source).cast<std::string>();
  ResolvedCase c{YAML::Node(), file, {}};
  c.root = load_case_yaml(file, sets, &c.applied);
  return c;
}

}  // namespace ckpd::python
