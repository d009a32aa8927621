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

}  // namespace ckpd
