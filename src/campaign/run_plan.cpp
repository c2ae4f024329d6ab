/// The grid, and every run's scenario checked and fingerprinted before any
/// run starts.
#include "rfsitl/campaign/run_plan.hpp"

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "rfsitl/scenario/scenario_loader.hpp"

namespace rfsitl::campaign {
namespace {

/// A setting as the child gets it (`--set key=value`) and where the campaign gave it.
struct Override {
  std::string key;
  const SettingValue* value;
};

/// The settings the campaign imposes on every run, as `rfsitl run` flags, in
/// the order that command applies them (its flag table's).
std::vector<std::string> imposed_flags(std::uint64_t seed) {
  return {"--mode", "virtual", "--seed", std::to_string(seed), "--threads", "1"};
}

void apply(scenario::Scenario& s, const CampaignSpec& spec, const std::vector<Override>& settings,
           std::uint64_t seed) {
  // As `rfsitl run` will: its flags first (table order), then each --set.
  scenario::apply_setting(s, "time.mode", "virtual", spec.source);
  scenario::apply_setting(s, "seed", std::to_string(seed), spec.source);
  scenario::apply_setting(s, "engine.threads", "1", spec.source);
  for (const Override& o : settings) {
    scenario::apply_setting(s, o.key, o.value->text,
                            spec.source + ":" + std::to_string(o.value->line));
  }
}

std::string file_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

std::vector<GridPoint> expand_grid(const CampaignSpec& spec) {
  std::size_t total = 1;
  for (const Axis& a : spec.axes) total *= a.size();
  std::vector<GridPoint> grid;
  grid.reserve(total);
  // Point p's index on each axis: p in mixed radix, the last axis fastest.
  for (std::size_t p = 0; p < total; ++p) {
    GridPoint point;
    std::size_t rest = p;
    std::vector<std::size_t> index(spec.axes.size());
    for (std::size_t a = spec.axes.size(); a-- > 0;) {
      index[a] = rest % spec.axes[a].size();
      rest /= spec.axes[a].size();
    }
    for (std::size_t a = 0; a < spec.axes.size(); ++a) {
      for (const auto& values : spec.axes[a].values) point.values.push_back(&values[index[a]]);
    }
    grid.push_back(std::move(point));
  }
  return grid;
}

std::vector<PlannedRun> plan_runs(const CampaignSpec& spec, const std::string& runs_dir) {
  scenario::Scenario base;
  try {
    base = scenario::load_scenario_file(spec.scenario_path);
  } catch (const scenario::ScenarioError& e) {
    throw CampaignError(spec.source + ":" + std::to_string(spec.scenario_line) +
                        ": scenario: " + e.what());
  }
  const std::string base_text = file_text(spec.scenario_path);
  const std::string base_path = std::filesystem::absolute(spec.scenario_path).string();
  const std::vector<std::string> keys = spec.parameter_keys();
  std::vector<PlannedRun> runs;
  const std::vector<GridPoint> grid = expand_grid(spec);
  for (std::size_t p = 0; p < grid.size(); ++p) {
    std::vector<Override> settings;
    for (const FixedSetting& f : spec.settings) settings.push_back({f.key, &f.value});
    for (std::size_t k = 0; k < keys.size(); ++k) settings.push_back({keys[k], grid[p].values[k]});
    // Validated once per point (the seed changes no rule), as the child will build it.
    scenario::Scenario s = base;
    try {
      apply(s, spec, settings, spec.seeds.front());
    } catch (const scenario::ScenarioError& e) {
      throw CampaignError(e.what());
    }
    if (!(s.timing.duration_s > 0)) {
      throw CampaignError(spec.source +
                          ": time.duration_s: a campaign's runs must end: give it "
                          "(> 0) in settings: or in the scenario " +
                          spec.scenario_path);
    }
    // The effective scenario: the base file's text and the settings over it.
    std::string effective = base_text;
    std::vector<std::string> set_flags;
    for (const Override& o : settings) {
      effective += '\0' + o.key + '=' + o.value->text;
      set_flags.push_back("--set");
      set_flags.push_back(o.key + "=" + o.value->text);
    }
    const std::string hash = fingerprint(effective);
    for (std::size_t si = 0; si < spec.seeds.size(); ++si) {
      PlannedRun run;
      run.point = p;
      run.seed_index = si;
      run.seed = spec.seeds[si];
      for (const SettingValue* v : grid[p].values) run.values.push_back(v->text);
      run.scenario_hash = hash;
      run.key = hash + "-s" + std::to_string(run.seed);
      run.arguments = {"run", base_path};
      for (auto& f : imposed_flags(run.seed)) run.arguments.push_back(std::move(f));
      for (const char* f : {"--no-ports", "--no-dashboard", "--no-preflight"}) {
        run.arguments.emplace_back(f);
      }
      run.arguments.insert(run.arguments.end(), set_flags.begin(), set_flags.end());
      run.arguments.push_back("--summary-json");
      run.arguments.push_back(
          (std::filesystem::absolute(runs_dir) / run.key / "summary.json").string());
      runs.push_back(std::move(run));
    }
  }
  return runs;
}

std::string fingerprint(std::string_view text) {
  std::uint64_t h = 14695981039346656037ULL;  // FNV-1a 64 offset basis
  for (const char c : text) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ULL;  // FNV prime
  }
  std::array<char, 17> hex{};
  std::snprintf(hex.data(), hex.size(), "%016llx", static_cast<unsigned long long>(h));
  return hex.data();
}

std::string shell_line(const std::vector<std::string>& args) {
  std::string line;
  for (const std::string& a : args) {
    if (!line.empty()) line += ' ';
    const bool plain = !a.empty() && a.find_first_not_of(
                                         "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLM"
                                         "NOPQRSTUVWXYZ0123456789_-.,/=:+@%") == std::string::npos;
    if (plain) {
      line += a;
      continue;
    }
    line += '\'';
    for (const char c : a) line += c == '\'' ? std::string("'\\''") : std::string(1, c);
    line += '\'';
  }
  return line;
}

}  // namespace rfsitl::campaign
