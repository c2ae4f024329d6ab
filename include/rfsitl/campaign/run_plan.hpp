#pragma once
/// The campaign's runs: the grid expanded, every grid point's scenario built
/// and validated before the first run, and for each run the command that runs
/// it (and re-runs it bit for bit).
#include <cstdint>
#include <string>
#include <vector>

#include "rfsitl/campaign/campaign_spec.hpp"

namespace rfsitl::campaign {

/// One point of the grid: a value for every parameter key.
struct GridPoint {
  std::vector<const SettingValue*> values;  ///< by CampaignSpec::parameter_keys(); into the spec
};

/// The grid in its fixed order: the cartesian product of the axes, the first
/// axis outermost (it changes slowest), a zip group's keys together. No axes:
/// one point. The pointers are into `spec`, which must outlive the result.
std::vector<GridPoint> expand_grid(const CampaignSpec& spec);

/// One run: a grid point with one seed.
struct PlannedRun {
  std::size_t point = 0;            ///< index into the grid
  std::size_t seed_index = 0;       ///< index into CampaignSpec::seeds
  std::vector<std::string> values;  ///< the parameters' values (as written)
  std::uint64_t seed = 0;
  std::string scenario_hash;  ///< of the run's effective scenario text (no seed)
  std::string key;            ///< "<hash>-s<seed>": its folder under runs/
  /// `rfsitl run` arguments after the program (its summary JSON last).
  std::vector<std::string> arguments;
};

/// Runs in table order: grid order, then seed order. Every grid point's
/// scenario is built (base file, settings, parameters, as the child will) and
/// validated first; the first problem throws CampaignError naming the
/// campaign file's line and the key ("sweep.yaml:9: channel.noise_db: ...").
/// `runs_dir`: where the runs' summaries go (the output's runs/).
std::vector<PlannedRun> plan_runs(const CampaignSpec& spec, const std::string& runs_dir);

/// 64-bit FNV-1a of `text`, as 16 hex digits: a fingerprint, not a MAC.
std::string fingerprint(std::string_view text);

/// `args` as one line a POSIX shell reads back as those words.
std::string shell_line(const std::vector<std::string>& args);

}  // namespace rfsitl::campaign
