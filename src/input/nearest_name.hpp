#pragma once
// "Did you mean ...?" for misspelt names: the known name nearest to an unknown one by edit
// distance (insertions, deletions, substitutions and swaps of neighbours each count one).
#include <string>
#include <vector>

namespace ckpd {

std::size_t edit_distance(const std::string& a, const std::string& b);

// The candidate nearest to `name` when it is close enough to be a slip of the keyboard (at most
// a third of the longer name's letters, and at most 3, differ); "" otherwise.
std::string nearest_name(const std::string& name, const std::vector<std::string>& candidates);

// " (did you mean 'x'?)" or "".
std::string did_you_mean(const std::string& name, const std::vector<std::string>& candidates);

// "a, b, c": the names for an error message's list of known ones.
std::string join_names(const std::vector<std::string>& names);

// Tables of named rows (fields, history quantities): the row called `name` (null if none) and
// the rows' names in order.
template <class Rows>
auto find_row(const Rows& rows, const std::string& name) -> decltype(&*rows.begin()) {
  for (const auto& row : rows)
    if (row.name == name) return &row;
  return nullptr;
}
template <class Rows>
std::vector<std::string> row_names(const Rows& rows) {
  std::vector<std::string> names;
  for (const auto& row : rows) names.push_back(row.name);
  return names;
}

}  // namespace ckpd
