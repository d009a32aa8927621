#include "src/sweep/csv.hpp"

#include <fstream>
#include <stdexcept>

namespace ckpd::sweep {

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string q = "\"";
  for (char c : text) {
    if (c == '"') q += '"';
    q += c;
  }
  return q + '"';
}

std::string csv_line(const std::vector<std::string>& fields) {
  std::string line;
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (i) line += ',';
    line += csv_field(fields[i]);
  }
  return line;
}

std::vector<std::string> split_line(const std::string& line, char delimiter) {
  std::vector<std::string> out;
  if (delimiter == ' ') {
    std::string cur;
    for (char c : line) {
      if (c == ' ' || c == '\t') {
        if (!cur.empty()) out.push_back(cur);
        cur.clear();
      } else {
        cur += c;
      }
    }
    if (!cur.empty()) out.push_back(cur);
    return out;
  }
  std::string cur;
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        cur += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        cur += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == delimiter) {
      out.push_back(cur);
      cur.clear();
    } else if (c != '\r') {
      cur += c;
    }
  }
  if (quoted) throw std::invalid_argument("unclosed quote");
  out.push_back(cur);
  return out;
}

TextTable read_table(const std::string& file, char delimiter) {
  std::ifstream in(file);
  if (!in) throw std::invalid_argument(file + ": cannot read the table");
  TextTable t;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    if (delimiter == 0)
      delimiter = line.find('\t') != std::string::npos  ? '\t'
                  : line.find(',') != std::string::npos ? ','
                                                        : ' ';
    std::vector<std::string> fields;
    try {
      fields = split_line(line, delimiter);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(file + ":" + std::to_string(number) + ": " + e.what());
    }
    for (std::string& f : fields) {
      const std::size_t a = f.find_first_not_of(" \t"), b = f.find_last_not_of(" \t");
      f = a == std::string::npos ? "" : f.substr(a, b - a + 1);
    }
    if (t.header.empty()) {
      t.header = fields;
      continue;
    }
    if (fields.size() != t.header.size())
      throw std::invalid_argument(file + ":" + std::to_string(number) + ": " +
                                  std::to_string(fields.size()) + " fields, the header has " +
                                  std::to_string(t.header.size()));
    t.rows.push_back(fields);
    t.lines.push_back(number);
  }
  if (t.header.empty()) throw std::invalid_argument(file + ": no header line");
  return t;
}

}  // namespace ckpd::sweep
