/// The campaign file's reader: its shape only (run_plan.cpp checks the settings
/// against the scenario).
#include "rfsitl/campaign/campaign_spec.hpp"

#include <yaml-cpp/yaml.h>

#include <array>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <set>

namespace rfsitl::campaign {
namespace {

constexpr std::size_t kMaxCampaignBytes = std::size_t{1} << 20;
constexpr std::size_t kMaxSeeds = 100000;
constexpr std::size_t kMaxRuns = 1000000;

/// Errors of one file: "<source>:<line>: <key>: <reason>".
struct Reader {
  const std::string& source;

  [[noreturn]] void fail(int line, const std::string& key, const std::string& why) const {
    std::string where = source;
    if (line > 0) where += ":" + std::to_string(line);
    throw CampaignError(where + ": " + key + ": " + why);
  }
  static int line_of(const YAML::Node& n) { return n.Mark().is_null() ? 0 : n.Mark().line + 1; }
};

std::string resolve(const std::string& folder, const std::string& path) {
  const std::filesystem::path p(path);
  if (p.is_absolute() || folder.empty()) return p.lexically_normal().string();
  return (std::filesystem::path(folder) / p).lexically_normal().string();
}

/// A setting's value: a scalar (a list or map is no scenario setting's value).
SettingValue scalar_value(const Reader& r, const YAML::Node& v, const std::string& key) {
  if (!v.IsScalar()) r.fail(Reader::line_of(v), key, "a value must be a single value (a scalar)");
  return {v.Scalar(), Reader::line_of(v)};
}

void check_key(const Reader& r, const YAML::Node& k, std::set<std::string>& seen) {
  const std::string key = k.IsScalar() ? k.Scalar() : "?";
  if (!k.IsScalar() || key.empty()) r.fail(Reader::line_of(k), key, "a key must be a dotted name");
  if (reserved_key(key)) {
    r.fail(Reader::line_of(k), key,
           "set by the campaign itself (seeds: gives the seeds; every run is virtual time on one "
           "engine thread)");
  }
  if (!seen.insert(key).second) {
    r.fail(Reader::line_of(k), key, "given twice (in settings:, parameters: or zip:)");
  }
}

/// A key's list of values (at least one).
std::vector<SettingValue> value_list(const Reader& r, const YAML::Node& list,
                                     const std::string& key) {
  if (!list.IsSequence() || list.size() == 0) {
    r.fail(Reader::line_of(list), key, "give a list of one or more values, e.g. [1, 2, 3]");
  }
  std::vector<SettingValue> out;
  for (const auto& v : list) out.push_back(scalar_value(r, v, key));
  return out;
}

void read_settings(const Reader& r, const YAML::Node& map, CampaignSpec& c,
                   std::set<std::string>& seen) {
  if (!map.IsMap()) r.fail(Reader::line_of(map), "settings", "must be a map of key: value");
  for (const auto& kv : map) {
    check_key(r, kv.first, seen);
    const std::string key = kv.first.Scalar();
    c.settings.push_back({key, scalar_value(r, kv.second, key)});
  }
}

void read_parameters(const Reader& r, const YAML::Node& map, CampaignSpec& c,
                     std::set<std::string>& seen) {
  if (!map.IsMap()) r.fail(Reader::line_of(map), "parameters", "must be a map of key: [values]");
  for (const auto& kv : map) {
    check_key(r, kv.first, seen);
    const std::string key = kv.first.Scalar();
    c.axes.push_back({{key}, {value_list(r, kv.second, key)}});
  }
}

void read_zip(const Reader& r, const YAML::Node& groups, CampaignSpec& c,
              std::set<std::string>& seen) {
  if (!groups.IsSequence()) {
    r.fail(Reader::line_of(groups), "zip", "must be a list of groups {key: [values], ...}");
  }
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const YAML::Node group = groups[g];
    const std::string name = "zip[" + std::to_string(g) + "]";
    if (!group.IsMap() || group.size() == 0) {
      r.fail(Reader::line_of(group), name, "must be a map of key: [values]");
    }
    Axis axis;
    for (const auto& kv : group) {
      check_key(r, kv.first, seen);
      const std::string key = kv.first.Scalar();
      axis.keys.push_back(key);
      axis.values.push_back(value_list(r, kv.second, key));
      if (axis.values.back().size() != axis.values.front().size()) {
        r.fail(Reader::line_of(kv.second), key,
               "a zip group's keys vary together: " + std::to_string(axis.values.back().size()) +
                   " values here, " + std::to_string(axis.values.front().size()) + " for " +
                   axis.keys.front());
      }
    }
    c.axes.push_back(std::move(axis));
  }
}

std::uint64_t unsigned_of(const Reader& r, const YAML::Node& v, const std::string& key) {
  const std::string text = v.IsScalar() ? v.Scalar() : "";
  std::uint64_t out = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size()) {
    r.fail(Reader::line_of(v), key, "must be a whole number >= 0, got '" + text + "'");
  }
  return out;
}

void read_seeds(const Reader& r, const YAML::Node& n, CampaignSpec& c) {
  if (n.IsScalar()) {
    const std::uint64_t count = unsigned_of(r, n, "seeds");
    if (count < 1 || count > kMaxSeeds) {
      r.fail(Reader::line_of(n), "seeds",
             "a count must be 1.." + std::to_string(kMaxSeeds) + " (or give a list)");
    }
    for (std::uint64_t s = 1; s <= count; ++s) c.seeds.push_back(s);
    return;
  }
  if (!n.IsSequence() || n.size() == 0 || n.size() > kMaxSeeds) {
    r.fail(Reader::line_of(n), "seeds", "give a count (10: seeds 1..10) or a list, e.g. [3, 7]");
  }
  std::set<std::uint64_t> seen;
  for (const auto& v : n) {
    const std::uint64_t s = unsigned_of(r, v, "seeds");
    if (!seen.insert(s).second)
      r.fail(Reader::line_of(v), "seeds", "seed " + v.Scalar() + " twice");
    c.seeds.push_back(s);
  }
}

std::string string_of(const Reader& r, const YAML::Node& v, const std::string& key) {
  if (!v.IsScalar() || v.Scalar().empty()) r.fail(Reader::line_of(v), key, "must be a path");
  return v.Scalar();
}

}  // namespace

std::vector<std::string> CampaignSpec::parameter_keys() const {
  std::vector<std::string> keys;
  for (const Axis& a : axes) keys.insert(keys.end(), a.keys.begin(), a.keys.end());
  return keys;
}

bool reserved_key(std::string_view key) {
  return key == "seed" || key == "time.mode" || key == "engine.threads";
}

CampaignSpec parse_campaign(std::string_view yaml_text, const std::string& source,
                            const std::string& folder) {
  const Reader r{source};
  YAML::Node root;
  try {
    root = YAML::Load(std::string(yaml_text));
  } catch (const YAML::Exception& e) {
    r.fail(e.mark.is_null() ? 0 : e.mark.line + 1, "YAML syntax", e.msg);
  }
  if (!root.IsMap()) r.fail(Reader::line_of(root), "campaign", "must be a map (scenario:, ...)");
  CampaignSpec c;
  c.source = source;
  std::set<std::string> seen;
  std::set<std::string> sections;
  bool have_seeds = false;
  for (const auto& kv : root) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : "?";
    const YAML::Node& v = kv.second;
    // YAML keeps a repeated key; a second seeds: would add to the first.
    if (!sections.insert(key).second) r.fail(Reader::line_of(kv.first), key, "given twice");
    if (key == "scenario") {
      c.scenario_path = resolve(folder, string_of(r, v, key));
      c.scenario_line = Reader::line_of(v);
    } else if (key == "output") {
      c.output_dir = resolve(folder, string_of(r, v, key));
    } else if (key == "settings") {
      read_settings(r, v, c, seen);
    } else if (key == "parameters") {
      read_parameters(r, v, c, seen);
    } else if (key == "zip") {
      read_zip(r, v, c, seen);
    } else if (key == "seeds") {
      read_seeds(r, v, c);
      have_seeds = true;
    } else if (key == "timeout_s") {
      double t = 0;
      try {
        t = v.as<double>();
      } catch (const YAML::Exception&) {
        t = -1;
      }
      if (!(t > 0 && t <= 1e6)) r.fail(Reader::line_of(v), key, "must be a number in (0, 1e6]");
      c.timeout_s = t;
    } else {
      r.fail(Reader::line_of(kv.first), key,
             "unknown key (scenario, output, settings, parameters, zip, seeds, timeout_s)");
    }
  }
  if (c.scenario_path.empty()) r.fail(0, "scenario", "missing: the base scenario file");
  if (!have_seeds) r.fail(0, "seeds", "missing: a count (10) or a list ([3, 7])");
  if (c.output_dir.empty()) {
    const std::string stem = std::filesystem::path(source).stem().string();
    c.output_dir = resolve(folder, (stem.empty() ? std::string("campaign") : stem) + ".results");
  }
  std::size_t runs = c.seeds.size();
  for (const Axis& a : c.axes) {
    if (runs > kMaxRuns / a.size()) {
      r.fail(0, "parameters", "more than " + std::to_string(kMaxRuns) + " runs");
    }
    runs *= a.size();
  }
  return c;
}

CampaignSpec load_campaign_file(const std::string& path) {
  const std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"),
                                                             &std::fclose);
  const auto unreadable = [&path](const std::string& why) {
    return CampaignError(path + ": cannot read campaign file: " + why);
  };
  if (!file) throw unreadable(std::strerror(errno));
  std::string text;
  std::array<char, 8192> buf{};
  for (std::size_t n; (n = std::fread(buf.data(), 1, buf.size(), file.get())) > 0;) {
    text.append(buf.data(), n);
    if (text.size() > kMaxCampaignBytes) throw unreadable("larger than 1 MiB");
  }
  if (std::ferror(file.get())) throw unreadable(std::strerror(errno));
  return parse_campaign(text, path, std::filesystem::path(path).parent_path().string());
}

}  // namespace rfsitl::campaign
