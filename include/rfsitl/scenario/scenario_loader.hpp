#pragma once
/// Reads and validates scenario files.
#include <stdexcept>
#include <string>
#include <string_view>

#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::scenario {

/// A scenario that cannot be used. what() reads "<source>:<line>: <key>: <reason>",
/// e.g. "six_uav.yaml:14: phy.bandwidth_time: must be in (0, 1), got 1.5".
class ScenarioError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Parses YAML text. `source` names the text in error messages (usually the path).
/// Unknown keys, wrong types, out-of-range values, duplicate node ids and port
/// ranges that do not fit in 1..65535 are errors. Throws ScenarioError.
Scenario parse_scenario(std::string_view yaml_text, const std::string& source);

/// Reads the file and parses it. Throws ScenarioError (also when unreadable).
Scenario load_scenario_file(const std::string& path);

/// Checks cross-field constraints of a scenario however it was built (also after
/// command-line overrides). Throws ScenarioError with source "scenario".
void validate_scenario(const Scenario& s);

}  // namespace rfsitl::scenario
