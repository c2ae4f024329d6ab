#pragma once
/// The campaign's table: one row per (grid point, seed), as CSV. Its bytes
/// depend only on the rows (no wall-clock figure, rows in the plan's order,
/// columns in a fixed order), so two campaigns with the same seeds write the
/// same file.
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace rfsitl::campaign {

/// A run's status in the table.
inline constexpr std::string_view kStatusOk = "ok";
inline constexpr std::string_view kStatusFailed = "failed";

struct ResultRow {
  std::vector<std::string> values;  ///< the parameters' values, by the table's parameter_keys
  std::uint64_t seed = 0;
  std::string scenario_hash;
  std::string status;  ///< kStatusOk or kStatusFailed
  std::string error;   ///< why it failed; "" when ok
  /// Figure name -> value as written ("123", "0.95"); absent: an empty cell.
  std::map<std::string, std::string> figures;

  /// What identifies the run: its values, seed and scenario hash.
  std::string identity() const;
};

struct ResultsTable {
  std::vector<std::string> parameter_keys;
  std::vector<ResultRow> rows;
};

/// The table as CSV (RFC 4180, "\n" line ends): the parameter columns, seed,
/// scenario_hash, status, error, then every figure any row has: the derived
/// figures first (run_figures.hpp's order), the counters in name order.
std::string to_csv(const ResultsTable& table);

/// Reads to_csv()'s output back. Throws CampaignError naming `source` and the
/// line when the text is not such a table or its parameter columns are not
/// `parameter_keys`.
ResultsTable parse_csv(std::string_view text, const std::string& source,
                       const std::vector<std::string>& parameter_keys);

}  // namespace rfsitl::campaign
