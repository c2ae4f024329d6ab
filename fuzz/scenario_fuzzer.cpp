/// Scenario files: parse_scenario on arbitrary YAML text; and when the text
/// is a JSON document, scenario_from_json on it (the Python module's dicts).
///
/// Checks, for both readers:
///  - the only exception that leaves parse_scenario is ScenarioError (its
///    contract), and its what() starts with "<source>:" as documented
///    ("fuzz.yaml:LINE: key: reason");
///  - a scenario it accepts passes validate_scenario (the checks that also run
///    after command-line overrides agree with the loader's), and every node id
///    is unique and within 1..kMaxNodeId.
#include <cstddef>
#include <cstdint>
#include <exception>
#include <set>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "fuzz_check.hpp"
#include "rfsitl/common/types.hpp"
#include "rfsitl/scenario/scenario_loader.hpp"

using rfsitl::scenario::ScenarioError;

namespace {

// One reader's contract: only ScenarioError leaves it, naming `source`; what
// it accepts passes validate_scenario, with unique node ids in range.
template <typename Read>
void check_reader(const std::string& source, Read read) {
  rfsitl::scenario::Scenario s;
  try {
    s = read();
  } catch (const ScenarioError& e) {
    const std::string what = e.what();
    FUZZ_CHECK(what.rfind(source + ":", 0) == 0, "error does not name the source: %s",
               what.c_str());
    return;
  } catch (const std::exception& e) {
    FUZZ_CHECK(false, "%s: threw something other than ScenarioError: %s", source.c_str(), e.what());
  }
  try {
    rfsitl::scenario::validate_scenario(s);
  } catch (const std::exception& e) {
    FUZZ_CHECK(false, "accepted scenario fails validate_scenario: %s", e.what());
  }
  std::set<rfsitl::NodeId> ids;
  for (const auto& n : s.nodes) {
    FUZZ_CHECK(n.id >= 1 && n.id <= rfsitl::kMaxNodeId, "node id %u", unsigned{n.id});
    FUZZ_CHECK(ids.insert(n.id).second, "duplicate node id %u", unsigned{n.id});
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // A copy of exactly `size` bytes (no terminator the parser could rely on).
  const std::string text(reinterpret_cast<const char*>(data), size);
  check_reader("fuzz.yaml", [&] {
    return rfsitl::scenario::parse_scenario(std::string_view(text.data(), text.size()),
                                            "fuzz.yaml");
  });
  const nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
  if (!doc.is_discarded()) {
    check_reader("fuzz.json",
                 [&] { return rfsitl::scenario::scenario_from_json(doc, "fuzz.json"); });
  }
  return 0;
}
