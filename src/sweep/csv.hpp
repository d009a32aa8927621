#pragma once
// Delimited text: sweep.csv (RFC 4180 quoting) and run tables given as files (comma-, tab- or
// whitespace-separated, as yade-batch users write them).
#include <string>
#include <vector>

namespace ckpd::sweep {

// Quotes a field when it holds the delimiter, a quote or a line break.
std::string csv_field(const std::string& text);
std::string csv_line(const std::vector<std::string>& fields);

// Splits one line with `delimiter` (',' or '\t', quotes honoured) or, for ' ', on runs of
// whitespace. Throws std::invalid_argument for an unclosed quote.
std::vector<std::string> split_line(const std::string& line, char delimiter);

// Reads a table: lines that are blank or start with '#' are skipped, the first other line is the
// header. `lines` gets each row's line number (1-based). Throws std::invalid_argument naming
// file and line for a row whose field count differs from the header's.
struct TextTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::vector<int> lines;
};
// delimiter 0: guess from the header (a tab, else a comma, else whitespace).
TextTable read_table(const std::string& file, char delimiter = 0);

}  // namespace ckpd::sweep
