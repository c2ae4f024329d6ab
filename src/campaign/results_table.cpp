/// The results table's CSV, written and read back (RFC 4180 quoting).
#include "rfsitl/campaign/results_table.hpp"

#include <algorithm>
#include <charconv>
#include <set>

#include "rfsitl/campaign/campaign_spec.hpp"
#include "rfsitl/campaign/run_figures.hpp"

namespace rfsitl::campaign {
namespace {

/// The columns before the figures, after the parameters.
const std::vector<std::string> kRunColumns = {"seed", "scenario_hash", "status", "error"};

std::string csv_cell(std::string_view cell) {
  if (cell.find_first_of(",\"\n\r") == std::string_view::npos) return std::string(cell);
  std::string out = "\"";
  for (const char c : cell) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

void write_line(std::string& out, const std::vector<std::string>& cells) {
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (i > 0) out += ',';
    out += csv_cell(cells[i]);
  }
  out += '\n';
}

/// The CSV's records, each with the line it starts on.
struct Record {
  int line;
  std::vector<std::string> cells;
};

std::vector<Record> records_of(std::string_view text, const std::string& source) {
  std::vector<Record> records;
  Record r{1, {""}};
  int line = 1;
  bool in_quotes = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_quotes) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        r.cells.back() += '"';
        ++i;
      } else if (c == '"') {
        in_quotes = false;
      } else {
        if (c == '\n') ++line;
        r.cells.back() += c;
      }
    } else if (c == '"' && r.cells.back().empty()) {
      in_quotes = true;
    } else if (c == ',') {
      r.cells.emplace_back();
    } else if (c == '\n') {
      records.push_back(std::move(r));
      r = Record{++line, {""}};
    } else if (c != '\r') {
      r.cells.back() += c;
    }
  }
  if (in_quotes) throw CampaignError(source + ":" + std::to_string(r.line) + ": unclosed quote");
  if (r.cells.size() > 1 || !r.cells.front().empty()) records.push_back(std::move(r));
  return records;
}

}  // namespace

std::string ResultRow::identity() const {
  std::string id;
  for (const std::string& v : values) id += v + '\0';
  return id + std::to_string(seed) + '\0' + scenario_hash;
}

std::string to_csv(const ResultsTable& table) {
  std::set<std::string> counters;
  for (const ResultRow& row : table.rows) {
    for (const auto& [name, value] : row.figures) counters.insert(name);
  }
  std::vector<std::string> figures;
  for (const std::string& d : derived_figure_names()) {
    figures.push_back(d);
    counters.erase(d);
  }
  figures.insert(figures.end(), counters.begin(), counters.end());
  std::string out;
  std::vector<std::string> header = table.parameter_keys;
  header.insert(header.end(), kRunColumns.begin(), kRunColumns.end());
  header.insert(header.end(), figures.begin(), figures.end());
  write_line(out, header);
  for (const ResultRow& row : table.rows) {
    std::vector<std::string> cells = row.values;
    cells.insert(cells.end(), {std::to_string(row.seed), row.scenario_hash, row.status, row.error});
    for (const std::string& f : figures) {
      const auto it = row.figures.find(f);
      cells.push_back(it == row.figures.end() ? "" : it->second);
    }
    write_line(out, cells);
  }
  return out;
}

ResultsTable parse_csv(std::string_view text, const std::string& source,
                       const std::vector<std::string>& parameter_keys) {
  const std::vector<Record> records = records_of(text, source);
  const auto fail = [&source](int line, const std::string& why) {
    return CampaignError(source + ":" + std::to_string(line) + ": " + why);
  };
  if (records.empty()) throw fail(1, "empty: no header line");
  const std::vector<std::string>& header = records.front().cells;
  const std::size_t p = parameter_keys.size();
  std::vector<std::string> expected = parameter_keys;
  expected.insert(expected.end(), kRunColumns.begin(), kRunColumns.end());
  if (header.size() < expected.size() ||
      !std::equal(expected.begin(), expected.end(), header.begin())) {
    std::string want;
    for (const auto& e : expected) want += (want.empty() ? "" : ",") + e;
    throw fail(1, "not this campaign's table: its columns must start " + want);
  }
  ResultsTable table{parameter_keys, {}};
  for (std::size_t r = 1; r < records.size(); ++r) {
    const Record& rec = records[r];
    if (rec.cells.size() != header.size()) {
      throw fail(rec.line, std::to_string(rec.cells.size()) + " cells, the header has " +
                               std::to_string(header.size()));
    }
    ResultRow row;
    row.values.assign(rec.cells.begin(), rec.cells.begin() + static_cast<std::ptrdiff_t>(p));
    const std::string& seed = rec.cells[p];
    const auto [end, ec] = std::from_chars(seed.data(), seed.data() + seed.size(), row.seed);
    if (seed.empty() || ec != std::errc() || end != seed.data() + seed.size()) {
      throw fail(rec.line, "seed: not a whole number: '" + seed + "'");
    }
    row.scenario_hash = rec.cells[p + 1];
    row.status = rec.cells[p + 2];
    if (row.status != kStatusOk && row.status != kStatusFailed) {
      throw fail(rec.line, "status: '" + row.status + "' (ok or failed)");
    }
    row.error = rec.cells[p + 3];
    for (std::size_t c = expected.size(); c < header.size(); ++c) {
      if (!rec.cells[c].empty()) row.figures[header[c]] = rec.cells[c];
    }
    table.rows.push_back(std::move(row));
  }
  return table;
}

}  // namespace rfsitl::campaign
