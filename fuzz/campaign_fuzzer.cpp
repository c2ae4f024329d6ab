/// Campaign files and their results tables (rfsitl sweep): parse_campaign on
/// arbitrary YAML text, parse_csv on arbitrary table text. The first byte
/// picks the parser; the rest is the text.
///
/// Checks:
///  - the only exception that leaves either parser is CampaignError, its
///    what() starting with the source ("fuzz.yaml", "fuzz.csv");
///  - an accepted campaign has a scenario, seeds without repeats, no reserved
///    key, every parameter key once, every axis non-empty with its keys'
///    value lists of one length; its grid has the product of the axes' sizes
///    as points, each with a value per key;
///  - an accepted table written again with to_csv reads back to the same text.
#include <cstddef>
#include <cstdint>
#include <exception>
#include <set>
#include <string>

#include "fuzz_check.hpp"
#include "rfsitl/campaign/campaign_spec.hpp"
#include "rfsitl/campaign/results_table.hpp"
#include "rfsitl/campaign/run_plan.hpp"

using rfsitl::campaign::CampaignError;

namespace {

void check_campaign(const std::string& text) {
  rfsitl::campaign::CampaignSpec c;
  try {
    c = rfsitl::campaign::parse_campaign(text, "fuzz.yaml", "dir");
  } catch (const CampaignError& e) {
    const std::string what = e.what();
    FUZZ_CHECK(what.rfind("fuzz.yaml", 0) == 0, "error does not name the source: %s", what.c_str());
    return;
  } catch (const std::exception& e) {
    FUZZ_CHECK(false, "parse_campaign threw something other than CampaignError: %s", e.what());
  }
  FUZZ_CHECK(!c.scenario_path.empty() && !c.output_dir.empty(), "no scenario or output");
  FUZZ_CHECK(!c.seeds.empty(), "no seeds");
  FUZZ_CHECK(std::set<std::uint64_t>(c.seeds.begin(), c.seeds.end()).size() == c.seeds.size(),
             "a seed repeats");
  std::set<std::string> keys;
  std::size_t points = 1;
  for (const auto& axis : c.axes) {
    FUZZ_CHECK(!axis.keys.empty() && axis.keys.size() == axis.values.size(), "axis shape");
    FUZZ_CHECK(axis.size() > 0, "an axis without values");
    for (std::size_t k = 0; k < axis.keys.size(); ++k) {
      FUZZ_CHECK(axis.values[k].size() == axis.size(), "a zip group's lists differ in length");
      FUZZ_CHECK(!rfsitl::campaign::reserved_key(axis.keys[k]), "reserved key %s",
                 axis.keys[k].c_str());
      FUZZ_CHECK(keys.insert(axis.keys[k]).second, "key %s twice", axis.keys[k].c_str());
    }
    points *= axis.size();
  }
  for (const auto& s : c.settings) {
    FUZZ_CHECK(!rfsitl::campaign::reserved_key(s.key), "reserved key %s", s.key.c_str());
    FUZZ_CHECK(keys.insert(s.key).second, "key %s twice", s.key.c_str());
  }
  if (points * c.seeds.size() > 10000) return;  // YAML aliases can make large grids: valid, slow
  const auto grid = rfsitl::campaign::expand_grid(c);
  FUZZ_CHECK(grid.size() == points, "grid of %zu points, axes make %zu", grid.size(), points);
  for (const auto& p : grid) {
    FUZZ_CHECK(p.values.size() == c.parameter_keys().size(), "a point without every key");
  }
}

void check_table(const std::string& text) {
  const std::vector<std::string> keys = {"a", "b"};
  rfsitl::campaign::ResultsTable t;
  try {
    t = rfsitl::campaign::parse_csv(text, "fuzz.csv", keys);
  } catch (const CampaignError& e) {
    const std::string what = e.what();
    FUZZ_CHECK(what.rfind("fuzz.csv:", 0) == 0, "error does not name the source: %s", what.c_str());
    return;
  } catch (const std::exception& e) {
    FUZZ_CHECK(false, "parse_csv threw something other than CampaignError: %s", e.what());
  }
  const std::string written = rfsitl::campaign::to_csv(t);
  std::string again;
  try {
    again = rfsitl::campaign::to_csv(rfsitl::campaign::parse_csv(written, "fuzz.csv", keys));
  } catch (const std::exception& e) {
    FUZZ_CHECK(false, "a written table does not read back: %s", e.what());
  }
  FUZZ_CHECK(again == written, "a written table reads back differently");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  if (data[0] % 2 == 0) {
    check_campaign(text);
  } else {
    check_table(text);
  }
  return 0;
}
