/// Scenario files: parse_scenario on arbitrary YAML text.
///
/// Checks:
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

#include "fuzz_check.hpp"
#include "rfsitl/common/types.hpp"
#include "rfsitl/scenario/scenario_loader.hpp"

using rfsitl::scenario::ScenarioError;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // A copy of exactly `size` bytes (no terminator the parser could rely on).
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::string source = "fuzz.yaml";
  rfsitl::scenario::Scenario s;
  try {
    s = rfsitl::scenario::parse_scenario(std::string_view(text.data(), text.size()), source);
  } catch (const ScenarioError& e) {
    const std::string what = e.what();
    FUZZ_CHECK(what.rfind(source + ":", 0) == 0, "error does not name the source: %s",
               what.c_str());
    return 0;
  } catch (const std::exception& e) {
    FUZZ_CHECK(false, "parse_scenario threw something other than ScenarioError: %s", e.what());
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
  return 0;
}
