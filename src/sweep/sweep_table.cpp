#include "src/sweep/sweep_table.hpp"

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>

#include "src/sweep/csv.hpp"
#include "src/sweep/generators.hpp"
#include "src/sweep/shard_check.hpp"

namespace ckpd::sweep {

Shard parse_shard(const std::string& text) {
  static const std::regex form("([0-9]{1,9})/([0-9]{1,9})");
  std::smatch m;
  if (!std::regex_match(text, m, form))
    throw SweepError("--shard " + text + ": expected I/N, e.g. 2/8 (the 2nd of 8 parts)");
  Shard s{std::stoi(m[1]), std::stoi(m[2])};
  if (s.count < 1 || s.index < 1 || s.index > s.count)
    throw SweepError("--shard " + text +
                     ": expected I/N with 1 <= I <= N (parts are numbered from 1)");
  return s;
}

std::vector<std::string> table_header(const Sweep& sweep) {
  std::vector<std::string> h{"index", "description", "hash", "folder"};
  for (const Parameter& p : sweep.parameters) h.push_back(p.name);
  h.push_back("status");
  h.push_back("message");
  for (const Metric& m : sweep.metrics) h.push_back(m.name);
  h.push_back("wall_seconds");
  return h;
}

void write_atomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc);
    out << text;
    out.flush();
    if (!out) throw std::runtime_error(tmp + ": cannot write");
  }
  std::filesystem::rename(tmp, path);
}

void write_sweep_table(const std::string& dir, const Sweep& sweep,
                       const std::vector<std::size_t>& runs,
                       const std::vector<RunRecord>& records) {
  std::string text = csv_line(table_header(sweep)) + "\n";
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const Run& run = sweep.runs[runs[k]];
    const RunRecord& rec = records[k];
    std::vector<std::string> row{std::to_string(run.index), run.description, run.hash, run.folder};
    for (const Value& v : run.values) row.push_back(v.text);
    row.push_back(rec.status);
    row.push_back(rec.message);
    for (std::size_t m = 0; m < sweep.metrics.size(); ++m)
      row.push_back(m < rec.metrics.size() ? rec.metrics[m] : "");
    row.push_back(rec.wall_seconds ? format_number(*rec.wall_seconds) : "");
    text += csv_line(row) + "\n";
  }
  write_atomically(dir + "/sweep.csv", text);
}

void write_sweep_meta(const std::string& dir, const Sweep& sweep, const Shard& shard) {
  nlohmann::ordered_json j;
  j["sweep_file"] = sweep.file;
  j["base"] = sweep.base;
  if (!sweep.description.empty()) j["description"] = sweep.description;
  j["sweep_id"] = sweep.id;
  j["runs"] = sweep.runs.size();
  j["shard"] = shard.text();
  j["columns"] = table_header(sweep);
  write_atomically(dir + "/sweep.json", j.dump(2) + "\n");
}

namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw SweepError(path + ": cannot read (is this a sweep output folder?)");
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Splits CSV text into records, honouring quoted line breaks.
std::vector<std::vector<std::string>> parse_csv(const std::string& text, const std::string& file) {
  std::vector<std::vector<std::string>> rows;
  std::string record;
  bool quoted = false;
  for (char c : text) {
    if (c == '"') quoted = !quoted;
    if (c == '\n' && !quoted) {
      if (!record.empty()) rows.push_back(split_line(record, ','));
      record.clear();
    } else {
      record += c;
    }
  }
  if (quoted) throw SweepError(file + ": unclosed quote");
  if (!record.empty()) rows.push_back(split_line(record, ','));
  return rows;
}

// The position of a column the merge reads; throws when the table has none.
std::size_t column(const std::vector<std::string>& header, const std::string& name,
                   const std::string& dir) {
  for (std::size_t c = 0; c < header.size(); ++c)
    if (header[c] == name) return c;
  throw SweepError(dir + "/sweep.csv: the header has no column '" + name + "'");
}

}  // namespace

std::size_t merge_sweep_tables(const std::vector<std::string>& dirs, const std::string& out,
                               bool allow_missing, std::string& report) {
  if (dirs.empty()) throw SweepError("sweep-merge: give the shards' output folders");
  ShardMeta first;
  std::vector<std::string> header;
  std::map<std::size_t, std::vector<std::string>> rows;
  std::map<std::size_t, std::string> source;
  std::size_t unbacked = 0;  // rows marked completed that their run folder does not back
  for (const std::string& dir : dirs) {
    const ShardMeta meta = read_shard_meta(dir);
    const auto table = parse_csv(read_text(dir + "/sweep.csv"), dir + "/sweep.csv");
    if (table.empty()) throw SweepError(dir + "/sweep.csv: empty");
    if (header.empty()) {
      first = meta;
      header = table[0];
    } else if (meta.sweep_id != first.sweep_id || meta.runs != first.runs || table[0] != header) {
      throw SweepError(dir + " holds another sweep (sweep_id " + meta.sweep_id.dump() + ", " +
                       dirs[0] + " has " + first.sweep_id.dump() +
                       "): merge shards of one sweep file");
    }
    const std::size_t total = first.runs;
    const std::size_t folder_col = column(header, "folder", dir);
    const std::size_t hash_col = column(header, "hash", dir);
    const std::size_t status_col = column(header, "status", dir);
    const std::string rel =
        std::filesystem::relative(std::filesystem::absolute(dir), std::filesystem::absolute(out))
            .lexically_normal()
            .string();
    for (std::size_t r = 1; r < table.size(); ++r) {
      std::vector<std::string> row = table[r];
      if (row.size() != header.size())
        throw SweepError(dir + "/sweep.csv: row " + std::to_string(r) + " has " +
                         std::to_string(row.size()) + " fields, the header " +
                         std::to_string(header.size()));
      const std::optional<std::size_t> parsed = parse_index(row[0]);
      if (!parsed)
        throw SweepError(dir + "/sweep.csv: row " + std::to_string(r) +
                         ": the index is not a run number: '" + row[0] + "'");
      const std::size_t index = *parsed;
      if (index >= total)
        throw SweepError(dir + "/sweep.csv: run " + row[0] + " is beyond the sweep's " +
                         std::to_string(total) + " runs");
      if (rows.count(index))
        throw SweepError("run " + row[0] + " is in both " + source[index] + " and " + dir +
                         ": the shards overlap");
      if (row[status_col] == "completed") {
        const std::string problem =
            completed_run_problem(dir + "/" + row[folder_col], row[hash_col]);
        if (!problem.empty()) {
          const std::string msg = dir + "/sweep.csv: run " + row[0] + " is marked completed but " +
                                  problem + ": run the shard again (ckpd sweep resumes it)";
          if (!allow_missing)
            throw SweepError("sweep-merge: " + msg +
                             ", or merge with "
                             "--allow-missing to leave it out");
          report += "warning: " + msg + "; left out\n";
          ++unbacked;
          continue;
        }
      }
      row[folder_col] = rel + "/" + row[folder_col];
      rows[index] = row;
      source[index] = dir;
    }
  }
  const std::size_t total = first.runs;
  std::vector<std::size_t> missing;
  for (std::size_t i = 0; i < total; ++i)
    if (!rows.count(i)) missing.push_back(i);
  if (missing.size() > unbacked) {
    std::string list;
    for (std::size_t k = 0; k < missing.size() && k < 20; ++k)
      list += (k ? ", " : "") + std::to_string(missing[k]);
    if (missing.size() > 20) list += ", ...";
    const std::string msg = std::to_string(missing.size()) + " of " + std::to_string(total) +
                            " runs missing (" + list + "): a shard is absent";
    if (!allow_missing) throw SweepError("sweep-merge: " + msg);
    report += "warning: " + msg + "\n";
  }
  const std::size_t status_col = column(header, "status", dirs[0]);
  std::size_t unfinished = 0;
  std::string text = csv_line(header) + "\n";
  for (const auto& [index, row] : rows) {
    text += csv_line(row) + "\n";
    if (row[status_col] != "completed") ++unfinished;
  }
  std::filesystem::create_directories(out);
  write_atomically(out + "/sweep.csv", text);
  nlohmann::ordered_json meta;
  meta["sweep_file"] = first.sweep_file;
  meta["base"] = first.base;
  meta["sweep_id"] = first.sweep_id;
  meta["runs"] = total;
  meta["shard"] = missing.empty() ? "1/1" : "partial";
  meta["merged_from"] = dirs;
  meta["columns"] = header;
  write_atomically(out + "/sweep.json", meta.dump(2) + "\n");
  report += "merged " + std::to_string(rows.size()) + " of " + std::to_string(total) +
            " runs from " + std::to_string(dirs.size()) + " tables into " + out + "/sweep.csv; " +
            std::to_string(unfinished) + " not completed\n";
  return unfinished + missing.size();
}

}  // namespace ckpd::sweep
