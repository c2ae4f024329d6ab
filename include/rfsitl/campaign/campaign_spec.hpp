#pragma once
/// A campaign file: a base scenario, the settings every run shares, the
/// parameters that vary (a grid), the seeds, where the results go.
///
///   scenario: ../../scenarios/six_uav_batch.yaml   # relative to this file
///   output: noise_sweep.results                    # default: <file name>.results
///   settings: {time.duration_s: 10}                # every run
///   parameters:                                    # one axis each (cartesian)
///     channel.noise_power_db: [-120, -60, -40]
///     mac.type: [none, csma]
///   zip:                                           # keys that vary together
///     - {phy.type: [gmsk, ofdm], phy.max_payload_bytes: [2048, 1500]}
///   seeds: 10                                      # 1..10, or a list [3, 7]
///   timeout_s: 600                                 # wall seconds per run
///
/// Keys are the scenario file's dotted keys (scenario::apply_setting).
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace rfsitl::campaign {

/// A campaign that cannot be used. what() reads "<file>:<line>: <key>: <reason>".
class CampaignError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A setting's value as the campaign file wrote it, and where.
struct SettingValue {
  std::string text;  ///< the YAML scalar, e.g. "-120", "csma"
  int line = 0;      ///< 1-based line in the campaign file
};

/// One fixed setting, applied to every run.
struct FixedSetting {
  std::string key;
  SettingValue value;
};

/// One dimension of the grid: one key (`parameters:`) or several keys that
/// take their i-th values together (a `zip:` group). Every key has the same
/// number of values.
struct Axis {
  std::vector<std::string> keys;
  std::vector<std::vector<SettingValue>> values;  ///< values[k][i]: key k's i-th value
  std::size_t size() const { return values.empty() ? 0 : values.front().size(); }
};

struct CampaignSpec {
  std::string source;         ///< the campaign file as given (what errors name)
  std::string scenario_path;  ///< the base scenario, resolved against the file's folder
  int scenario_line = 0;
  std::string output_dir;  ///< resolved against the file's folder
  std::vector<FixedSetting> settings;
  std::vector<Axis> axes;  ///< file order: `parameters:` keys, then `zip:` groups
  std::vector<std::uint64_t> seeds;
  double timeout_s = 600.0;

  /// Every varying key, axis by axis: the table's parameter columns.
  std::vector<std::string> parameter_keys() const;
};

/// Keys a campaign sets itself and its file may not: the seed (`seeds:`), the
/// time mode (virtual) and the engine's threads (one per run).
bool reserved_key(std::string_view key);

/// Parses a campaign's YAML text. `source` names it in errors; `folder` is
/// where relative paths start (the file's folder; "" for the current one).
/// Checks the file's shape only (keys, types, lengths, seeds); whether the
/// settings suit the scenario is plan_runs()'s (run_plan.hpp). Throws
/// CampaignError.
CampaignSpec parse_campaign(std::string_view yaml_text, const std::string& source,
                            const std::string& folder);

/// Reads the file and parses it. Throws CampaignError (also when unreadable).
CampaignSpec load_campaign_file(const std::string& path);

}  // namespace rfsitl::campaign
