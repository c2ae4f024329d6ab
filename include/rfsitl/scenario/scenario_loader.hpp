#pragma once
/// Reads and validates scenario files.
#include <stdexcept>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

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

/// Reads a scenario given as a JSON document (what a Python dict becomes)
/// with a file's readers and rules: strings are text, numbers and booleans
/// plain values, exactly as a file would quote them. Errors read "<source>:
/// <key>: <reason>", the key being the path in the document
/// ("nodes[1].phy.type"); a document has no lines. Relative paths of data
/// files (mobility traces, antenna patterns) are taken from `base_dir` ("":
/// the working folder). Throws ScenarioError.
Scenario scenario_from_json(const nlohmann::json& document, const std::string& source,
                            const std::string& base_dir = "");

/// Reads the file and parses it. Throws ScenarioError (also when unreadable).
Scenario load_scenario_file(const std::string& path);

/// Checks cross-field constraints of a scenario however it was built. Throws
/// ScenarioError with source "scenario".
void validate_scenario(const Scenario& s);

/// The reason a component that follows the wall clock (a live position
/// source) cannot run in `t`'s virtual time, naming where the mode was given:
/// "follows live vehicles on the wall clock, which virtual time cannot
/// (time.mode virtual at mob.yaml:3; ...)". For errors that start with the
/// component's name or the flag that chose it.
std::string wall_clock_conflict(const TimingConfig& t);

/// Sets one setting as if the file had said `dotted_key: value` (e.g.
/// "channel.noise_power_db", "400"), with the file's rules for its type and
/// range, then validates the whole scenario. Errors read "<source>: <key>:
/// <reason>" (source: e.g. "--noise-db"). Nodes and traffic cannot be set this
/// way. Throws ScenarioError; `s` may then be partly changed.
void apply_setting(Scenario& s, std::string_view dotted_key, std::string_view value,
                   const std::string& source);

}  // namespace rfsitl::scenario
