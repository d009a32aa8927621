#include "src/sweep/sweep_file.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <regex>
#include <set>

#include "src/input/yaml_document.hpp"
#include "src/sweep/csv.hpp"
#include "src/sweep/expression.hpp"
#include "src/sweep/generators.hpp"
#include "src/sweep/json_path.hpp"
#include "src/sweep/run_key.hpp"

namespace ckpd::sweep {

Value make_value(const std::string& text) {
  Value v{text, std::nullopt};
  char* end = nullptr;
  const double d = std::strtod(text.c_str(), &end);
  if (!text.empty() && end == text.c_str() + text.size() && std::isfinite(d)) v.number = d;
  return v;
}

Value make_value(double number) {
  return Value{format_number(number), number};
}

namespace {

const std::set<std::string> kReservedColumns{"index",  "description", "hash",        "folder",
                                             "status", "message",     "wall_seconds"};

enum class Kind { list, sampled, derived, table };

struct Spec {
  Parameter parameter;
  Kind kind = Kind::list;
  std::vector<Value> values;  // list: the values
  SampleRange range;          // sampled
  std::optional<Expression> expr;
  std::string group;  // zip group ("" = an axis of its own)
  std::string where;  // "file:line: parameters.NAME"
};

[[noreturn]] void fail_at(const CaseNode& n, const std::string& message) {
  throw SweepError(n.where() + ": " + message);
}

// A YAML value as `--set` text: scalars as written, lists and maps in flow style.
std::string yaml_text(const YAML::Node& node) {
  if (node.IsScalar()) return node.Scalar();
  YAML::Emitter out;
  out.SetSeqFormat(YAML::Flow);
  out.SetMapFormat(YAML::Flow);
  out << node;
  return out.c_str();
}

// Empty when `key` (dots; list elements by index or `name`) leads to an existing value of
// `root`; otherwise the part that is missing.
std::string missing_part(const YAML::Node& root, const std::string& key) {
  YAML::Node node = root;
  std::string walked;
  std::size_t start = 0;
  for (;;) {
    const std::size_t dot = key.find('.', start);
    const std::string part = key.substr(start, dot == std::string::npos ? dot : dot - start);
    walked += (walked.empty() ? "" : ".") + part;
    YAML::Node next;
    bool found = false;
    if (part.empty()) return walked.empty() ? "(empty key)" : walked + " (empty key)";
    if (node.IsMap() && node[part]) {
      next.reset(node[part]);
      found = true;
    } else if (node.IsSequence()) {
      const std::optional<std::size_t> index = parse_index(part);
      for (std::size_t e = 0; e < node.size() && !found; ++e) {
        if ((index && *index == e) ||
            (node[e].IsMap() && node[e]["name"] && node[e]["name"].Scalar() == part)) {
          next.reset(node[e]);
          found = true;
        }
      }
    }
    if (!found) return walked;
    if (dot == std::string::npos) return "";
    node.reset(next);
    start = dot + 1;
  }
}

Spec read_parameter(const std::string& name, const CaseNode& n, bool sampling) {
  Spec s;
  s.parameter.name = name;
  s.parameter.line = n.yaml().Mark().line + 1;
  s.where = n.where();
  static const std::regex identifier("[A-Za-z_][A-Za-z0-9_]*");
  if (!std::regex_match(name, identifier))
    fail_at(n,
            "a parameter name is a letter or '_' followed by letters, digits and '_' (it is "
            "used in expressions), not '" +
                name + "'");
  if (kReservedColumns.count(name))
    fail_at(n, "'" + name + "' is a column of sweep.csv; give the parameter another name");
  if (!n.is_map())
    fail_at(n,
            "expected a map {key, values | range | expr, zip}, e.g. {key: "
            "bodies.disc.spacing, values: [0.01, 0.02]}");
  if (auto k = n.optional("key")) s.parameter.key = k->as_string();
  int given = 0;
  if (n.has("values")) {
    ++given;
    const CaseNode v = n.required("values");
    if (!v.is_sequence()) v.fail("a list of values");
    for (const CaseNode& e : v.elements()) s.values.push_back(make_value(yaml_text(e.yaml())));
    if (s.values.empty()) fail_at(v, "an empty list of values: give at least one");
  }
  if (n.has("range")) {
    ++given;
    const CaseNode r = n.required("range");
    if (!r.is_map())
      fail_at(r, "a malformed range: expected a map {from, to, count, scale: linear | log}");
    const double from = r.required("from").as_double();
    const double to = r.required("to").as_double();
    bool log = false;
    if (auto sc = r.optional("scale")) {
      const std::string t = sc->as_string();
      if (t != "linear" && t != "log") sc->fail("linear or log");
      log = t == "log";
    }
    if (log && !(from > 0 && to > 0))
      fail_at(r, "a malformed range: a log range needs from > 0 and to > 0");
    if (sampling) {
      if (r.has("count"))
        fail_at(r,
                "no count: with combine random or latin_hypercube the range is sampled "
                "`samples` times");
      if (!(to > from)) fail_at(r, "a malformed range: a sampled range needs to > from");
      s.kind = Kind::sampled;
      s.range = SampleRange{from, to, log};
    } else {
      const CaseNode c = r.required("count");
      const long long count = c.as_integer();
      if (count < 1 || count > kMaxRuns)
        c.fail("a count from 1 to " + std::to_string(kMaxRuns) + " (the most runs of a sweep)");
      if (count > 1 && from == to) fail_at(r, "a malformed range: from equals to");
      for (double x : log ? log_range(from, to, static_cast<int>(count))
                          : linear_range(from, to, static_cast<int>(count)))
        s.values.push_back(make_value(x));
    }
    r.finish();
  }
  if (n.has("expr")) {
    ++given;
    const CaseNode e = n.required("expr");
    try {
      s.expr.emplace(e.as_string());
    } catch (const ExpressionError& err) {
      fail_at(e, err.what());
    }
    s.kind = Kind::derived;
    s.parameter.derived = true;
  }
  if (auto z = n.optional("zip")) {
    s.group = z->as_string();
    if (s.kind != Kind::list || given == 0) fail_at(*z, "zip only with values or a counted range");
  }
  if (given > 1) fail_at(n, "one of values, range or expr, not several");
  if (given == 0) s.kind = Kind::table;  // its values come from the table (checked later)
  n.finish();
  return s;
}

// The run table: inline (a list of maps) or a file (CSV, TSV or whitespace-separated).
struct TableRows {
  std::vector<std::string> descriptions;
  std::vector<std::map<std::string, std::string>> rows;
  std::vector<std::string> where;  // per row
};

TableRows read_run_table(const CaseNode& t, const std::string& sweep_dir,
                         const std::set<std::string>& columns) {
  TableRows out;
  auto check = [&](const std::map<std::string, std::string>& row, const std::string& where) {
    for (const auto& [k, v] : row)
      if (!columns.count(k)) {
        std::string list;
        for (const auto& c : columns) list += (list.empty() ? "" : ", ") + c;
        throw SweepError(where + ": column '" + k + "' is not a table parameter (a parameter " +
                         "declared without values, range or expr: " + list + ")");
      }
    for (const auto& c : columns)
      if (!row.count(c)) throw SweepError(where + ": missing the value of '" + c + "'");
  };
  if (t.is_scalar()) {
    std::filesystem::path file = t.as_string();
    if (file.is_relative()) file = std::filesystem::path(sweep_dir) / file;
    TextTable table;
    try {
      table = read_table(file.lexically_normal().string());
    } catch (const std::invalid_argument& e) {
      fail_at(t, e.what());
    }
    for (std::size_t r = 0; r < table.rows.size(); ++r) {
      std::map<std::string, std::string> row;
      std::string description;
      for (std::size_t c = 0; c < table.header.size(); ++c) {
        if (table.header[c] == "description")
          description = table.rows[r][c];
        else
          row[table.header[c]] = table.rows[r][c];
      }
      const std::string where =
          file.lexically_normal().string() + ":" + std::to_string(table.lines[r]);
      check(row, where);
      out.descriptions.push_back(description);
      out.rows.push_back(row);
      out.where.push_back(where);
    }
  } else {
    for (const CaseNode& e : t.elements()) {
      if (!e.is_map()) e.fail("a map {description, PARAMETER: value, ...}");
      std::map<std::string, std::string> row;
      std::string description;
      for (const auto& [k, v] : e.entries()) {
        if (k == "description")
          description = v.as_string();
        else
          row[k] = yaml_text(v.yaml());
      }
      check(row, e.where());
      out.descriptions.push_back(description);
      out.rows.push_back(row);
      out.where.push_back(e.where());
    }
  }
  if (out.rows.empty()) fail_at(t, "an empty run table: give at least one row");
  return out;
}

// One axis of the grid: rows of values for some parameters that move together.
struct Axis {
  std::vector<std::size_t> params;
  std::vector<std::vector<Value>> rows;   // rows[k][j]: value of params[j]
  std::vector<std::string> descriptions;  // per row (the table's), or empty
};

std::string substitute(const std::string& label, const std::vector<Spec>& specs,
                       const std::vector<Value>& values, const CaseNode* where) {
  std::string out;
  for (std::size_t i = 0; i < label.size(); ++i) {
    if (label[i] != '{') {
      out += label[i];
      continue;
    }
    const std::size_t close = label.find('}', i);
    const std::string name = close == std::string::npos ? "" : label.substr(i + 1, close - i - 1);
    std::size_t p = 0;
    while (p < specs.size() && specs[p].parameter.name != name) ++p;
    if (p == specs.size()) {
      if (where) fail_at(*where, "{" + name + "} in the label is not a parameter");
      return label;
    }
    out += values[p].text;
    i = close;
  }
  return out;
}

}  // namespace

Sweep load_sweep(const std::string& file) {
  YAML::Node yaml;
  try {
    // The case files' checks: aliases, size, depth, keys given twice or not plain names.
    yaml = load_yaml_file(file, "sweep file");
  } catch (const CaseError& e) {
    throw SweepError(e.what());
  }
  if (!yaml.IsMap()) throw SweepError(file + ": a sweep file is a map (base, parameters, ...)");
  const CaseNode root(yaml, file);
  Sweep sweep;
  sweep.file = file;
  const std::string dir = std::filesystem::path(file).parent_path().string();

  const CaseNode base = root.required("base");
  std::filesystem::path base_path = base.as_string();
  if (base_path.is_relative()) base_path = std::filesystem::path(dir) / base_path;
  sweep.base = base_path.lexically_normal().string();
  if (!std::filesystem::is_regular_file(sweep.base))
    fail_at(base, "the base case " + sweep.base +
                      " does not exist (the path is relative to the "
                      "sweep file's folder)");
  if (auto d = root.optional("description")) sweep.description = d->as_string();

  // Fixed overrides, checked one by one so that an error names its line.
  if (auto set = root.optional("set")) {
    for (const auto& [key, value] : set->entries()) {
      sweep.fixed.push_back(key + "=" + yaml_text(value.yaml()));
      try {
        load_case_yaml(sweep.base, sweep.fixed);
      } catch (const CaseError& e) {
        fail_at(value, e.what());
      }
    }
  }
  const YAML::Node base_case = load_case_yaml(sweep.base, sweep.fixed);

  std::string combine = "grid";
  std::optional<CaseNode> combine_node = root.optional("combine");
  if (combine_node) {
    combine = combine_node->as_string();
    if (combine != "grid" && combine != "zip" && combine != "random" &&
        combine != "latin_hypercube")
      combine_node->fail("grid, zip, random or latin_hypercube");
  }
  const bool sampling = combine == "random" || combine == "latin_hypercube";
  long long samples = 0;
  std::uint64_t seed = 1;
  if (auto s = root.optional("samples")) {
    if (!sampling) fail_at(*s, "samples only with combine: random or latin_hypercube");
    samples = s->as_integer();
    if (samples < 1 || samples > kMaxRuns)
      s->fail("a number of samples from 1 to " + std::to_string(kMaxRuns) +
              " (the most runs of a sweep)");
  } else if (sampling) {
    throw SweepError(root.where() + ": combine: " + combine + " needs `samples` (and `seed`)");
  }
  if (auto s = root.optional("seed")) {
    if (!sampling) fail_at(*s, "seed only with combine: random or latin_hypercube");
    const long long v = s->as_integer();
    if (v < 0) s->fail("a non-negative integer");
    seed = static_cast<std::uint64_t>(v);
  }

  // Parameters, in file order.
  std::vector<Spec> specs;
  const CaseNode params = root.required("parameters");
  for (const auto& [name, node] : params.entries()) {
    specs.push_back(read_parameter(name, node, sampling));
    Spec& s = specs.back();
    if (combine == "zip" && s.kind == Kind::list) s.group = "(all)";
    if (!s.parameter.key.empty()) {
      const std::string missing = missing_part(base_case, s.parameter.key);
      if (!missing.empty())
        throw SweepError(s.where + ".key: '" + s.parameter.key +
                         "' does not exist in the base case " + sweep.base + " (no '" + missing +
                         "')");
    }
    sweep.parameters.push_back(s.parameter);
  }
  if (specs.empty()) fail_at(params, "at least one parameter");
  // A key set twice would silently take the last value: by two parameters, or by `set:` and a
  // parameter.
  {
    std::map<std::string, std::string> set_by;  // key -> who sets it
    for (const std::string& f : sweep.fixed) set_by[f.substr(0, f.find('='))] = "set:";
    for (const Spec& s : specs) {
      if (s.parameter.key.empty()) continue;
      const auto [it, fresh] =
          set_by.emplace(s.parameter.key, "parameter '" + s.parameter.name + "'");
      if (!fresh)
        throw SweepError(s.where + ".key: '" + s.parameter.key + "' is set by " + it->second +
                         " already (one value per key and run)");
    }
  }
  std::map<std::string, std::size_t> index_of;
  for (std::size_t i = 0; i < specs.size(); ++i) index_of[specs[i].parameter.name] = i;

  // Derived values: every name they read must be a parameter; evaluation order without cycles.
  std::vector<std::size_t> derived_order;
  {
    std::set<std::size_t> done;
    for (std::size_t i = 0; i < specs.size(); ++i) {
      if (specs[i].kind != Kind::derived) {
        done.insert(i);
        continue;
      }
      for (const std::string& name : specs[i].expr->names())
        if (!index_of.count(name))
          throw SweepError(specs[i].where + ".expr: '" + name +
                           "' is not a parameter of this sweep");
    }
    for (bool progress = true; progress;) {
      progress = false;
      for (std::size_t i = 0; i < specs.size(); ++i) {
        if (done.count(i)) continue;
        bool ready = true;
        for (const std::string& name : specs[i].expr->names())
          ready = ready && done.count(index_of[name]);
        if (ready) {
          derived_order.push_back(i);
          done.insert(i);
          progress = true;
        }
      }
    }
    for (std::size_t i = 0; i < specs.size(); ++i)
      if (!done.count(i))
        throw SweepError(specs[i].where +
                         ".expr: the derived values depend on each other in a "
                         "cycle ('" +
                         specs[i].expr->text() + "')");
  }

  // Combine the values into runs (each: one Value per parameter, derived ones filled later).
  std::vector<std::vector<Value>> runs;
  std::vector<std::string> table_descriptions;
  const std::optional<CaseNode> table = root.optional("table");
  std::set<std::string> table_columns;
  for (const Spec& s : specs)
    if (s.kind == Kind::table) table_columns.insert(s.parameter.name);
  if (!table && !table_columns.empty())
    throw SweepError(specs[index_of[*table_columns.begin()]].where +
                     ": expected values, range or expr (or a `table` of runs)");
  if (table && table_columns.empty())
    fail_at(*table, "a table needs parameters declared without values (its columns)");
  if (sampling) {
    if (table) fail_at(*table, "no table with combine: " + combine);
    std::vector<SampleRange> dims;
    std::vector<std::size_t> which;
    for (std::size_t i = 0; i < specs.size(); ++i) {
      if (specs[i].kind == Kind::derived) continue;
      if (specs[i].kind != Kind::sampled)
        throw SweepError(specs[i].where + ": with combine: " + combine +
                         " every parameter is a range {from, to, scale} (sampled) or an expr");
      dims.push_back(specs[i].range);
      which.push_back(i);
    }
    const auto draws = combine == "random" ? random_samples(dims, static_cast<int>(samples), seed)
                                           : latin_hypercube(dims, static_cast<int>(samples), seed);
    for (const auto& draw : draws) {
      std::vector<Value> values(specs.size());
      for (std::size_t d = 0; d < which.size(); ++d) values[which[d]] = make_value(draw[d]);
      runs.push_back(values);
    }
  } else {
    std::vector<Axis> axes;
    std::map<std::string, std::size_t> group_axis;
    for (std::size_t i = 0; i < specs.size(); ++i) {
      const Spec& s = specs[i];
      if (s.kind == Kind::derived) continue;
      if (s.kind == Kind::table) {
        if (group_axis.count("(table)")) continue;
        const TableRows t = read_run_table(*table, dir, table_columns);
        Axis axis;
        for (const Spec& c : specs)
          if (c.kind == Kind::table) axis.params.push_back(index_of[c.parameter.name]);
        for (std::size_t r = 0; r < t.rows.size(); ++r) {
          std::vector<Value> row;
          for (std::size_t p : axis.params)
            row.push_back(make_value(t.rows[r].at(specs[p].parameter.name)));
          axis.rows.push_back(row);
        }
        axis.descriptions = t.descriptions;
        group_axis["(table)"] = axes.size();
        axes.push_back(axis);
        continue;
      }
      if (!s.group.empty() && group_axis.count(s.group)) {
        Axis& axis = axes[group_axis[s.group]];
        if (axis.rows.size() != s.values.size())
          throw SweepError(s.where + ": zipped with '" + specs[axis.params[0]].parameter.name +
                           "', which has " + std::to_string(axis.rows.size()) +
                           " values; this has " + std::to_string(s.values.size()));
        axis.params.push_back(i);
        for (std::size_t k = 0; k < s.values.size(); ++k) axis.rows[k].push_back(s.values[k]);
        continue;
      }
      Axis axis;
      axis.params.push_back(i);
      for (const Value& v : s.values) axis.rows.push_back({v});
      if (!s.group.empty()) group_axis[s.group] = axes.size();
      axes.push_back(axis);
    }
    if (axes.empty()) fail_at(params, "at least one parameter with values, range or a table");
    double total = 1;
    for (const Axis& a : axes) total *= static_cast<double>(a.rows.size());
    if (total > static_cast<double>(kMaxRuns))
      fail_at(params, "at most " + std::to_string(kMaxRuns) + " runs (the grid has " +
                          format_number(total) + "; split the study into several sweep files)");
    // The product, the first axis slowest (as nested loops in declaration order).
    std::vector<std::size_t> at(axes.size(), 0);
    for (;;) {
      std::vector<Value> values(specs.size());
      std::string description;
      for (std::size_t a = 0; a < axes.size(); ++a) {
        for (std::size_t j = 0; j < axes[a].params.size(); ++j)
          values[axes[a].params[j]] = axes[a].rows[at[a]][j];
        if (!axes[a].descriptions.empty()) description = axes[a].descriptions[at[a]];
      }
      runs.push_back(values);
      table_descriptions.push_back(description);
      std::size_t a = axes.size();
      while (a > 0 && ++at[a - 1] == axes[a - 1].rows.size()) at[--a] = 0;
      if (a == 0) break;
    }
  }

  const std::optional<CaseNode> label = root.optional("label");
  if (label) substitute(label->as_string(), specs, std::vector<Value>(specs.size()), &*label);

  // Metrics.
  if (auto m = root.optional("metrics")) {
    auto add = [&](const std::string& name, const CaseNode& path_node) {
      const std::string path = path_node.as_string();
      try {
        split_json_path(path);
      } catch (const std::invalid_argument& e) {
        fail_at(path_node, e.what());
      }
      if (kReservedColumns.count(name) || index_of.count(name))
        fail_at(path_node, "metric name '" + name + "' is already a column (give it another name)");
      for (const Metric& other : sweep.metrics)
        if (other.name == name) fail_at(path_node, "metric name '" + name + "' used twice");
      sweep.metrics.push_back({name, path});
    };
    if (m->is_sequence()) {
      for (const CaseNode& e : m->elements()) add(e.as_string(), e);
    } else {
      for (const auto& [name, path] : m->entries()) add(name, path);
    }
  }
  root.finish();

  // Resolve each run: derived values, overrides, the resolved case and its key.
  const std::size_t width = std::max<std::size_t>(4, std::to_string(runs.size() - 1).size());
  std::uint64_t id = fnv1a(sweep.base);
  for (std::size_t r = 0; r < runs.size(); ++r) {
    Run run;
    run.index = r;
    run.values = runs[r];
    for (std::size_t i : derived_order) {
      std::map<std::string, double> numbers;
      for (const std::string& name : specs[i].expr->names()) {
        const Value& v = run.values[index_of[name]];
        if (!v.number)
          throw SweepError(specs[i].where + ".expr: run " + std::to_string(r) + ": '" + name +
                           "' is '" + v.text + "', not a number");
        numbers[name] = *v.number;
      }
      try {
        run.values[i] = make_value(specs[i].expr->evaluate(numbers));
      } catch (const ExpressionError& e) {
        throw SweepError(specs[i].where + ".expr: run " + std::to_string(r) + ": " + e.what());
      }
    }
    if (label) {
      run.description = substitute(label->as_string(), specs, run.values, nullptr);
    } else {
      std::string parts;
      for (std::size_t i = 0; i < specs.size(); ++i)
        if (specs[i].kind != Kind::derived && specs[i].kind != Kind::table)
          parts += (parts.empty() ? "" : " ") + specs[i].parameter.name + "=" + run.values[i].text;
      const std::string& t = r < table_descriptions.size() ? table_descriptions[r] : "";
      run.description = t.empty() ? parts : parts.empty() ? t : t + " " + parts;
    }
    run.overrides = sweep.fixed;
    for (std::size_t i = 0; i < specs.size(); ++i)
      if (!specs[i].parameter.key.empty())
        run.overrides.push_back(specs[i].parameter.key + "=" + run.values[i].text);
    YAML::Node resolved;
    try {
      resolved = load_case_yaml(sweep.base, run.overrides);
    } catch (const CaseError& e) {
      throw SweepError(file + ": run " + std::to_string(r) + " (" + run.description +
                       "): " + e.what());
    }
    run.hash = run_key(resolved);
    std::string index = std::to_string(r);
    run.folder = std::string(width - index.size(), '0') + index + "-" + run.hash.substr(0, 8);
    id = fnv1a(run.hash + "\n", id);
    sweep.runs.push_back(std::move(run));
  }
  for (const Parameter& p : sweep.parameters) id = fnv1a(p.name + "\n", id);
  sweep.id = hex16(id);
  return sweep;
}

}  // namespace ckpd::sweep
