#include "scenario_assembly.hpp"

#include <fstream>
#include <iterator>

#include "rfsitl/scenario/default_formation.hpp"
#include "rfsitl/scenario/scenario_loader.hpp"
#include "rfsitl/session/live_sources.hpp"

namespace rfsitl::session {
namespace {

const std::string& origin_of(const SettingOverride& o) {
  return o.origin.empty() ? o.key : o.origin;
}

// A file refuses tick_samples beside tick_us; so do the overrides.
void refuse_both_ticks(const SessionOptions& o) {
  const SettingOverride* samples = nullptr;
  const SettingOverride* us = nullptr;
  for (const auto& s : o.settings) {
    if (s.key == "time.tick_samples") samples = &s;
    if (s.key == "time.tick_us") us = &s;
  }
  if (samples != nullptr && us != nullptr) {
    throw scenario::ScenarioError(origin_of(*us) + ": give the tick as " + origin_of(*samples) +
                                  " or as " + origin_of(*us) + ", not both");
  }
}

}  // namespace

scenario::Scenario assemble_scenario(const SessionOptions& o) {
  scenario::Scenario s;
  const bool formation = !o.scenario && o.scenario_path.empty();
  if (o.scenario && !o.scenario_path.empty()) {
    throw scenario::ScenarioError("a session takes a scenario file or a ready-made scenario (" +
                                  o.scenario_path + "), not both");
  }
  if (!formation && o.nodes) {
    throw scenario::ScenarioError(
        "--nodes builds the default formation and cannot be combined with a scenario file (" +
        (o.scenario_path.empty() ? std::string("a ready-made scenario") : o.scenario_path) +
        " lists its own nodes)");
  }
  if (o.scenario) {
    s = *o.scenario;
  } else if (!o.scenario_path.empty()) {
    s = scenario::load_scenario_file(o.scenario_path);
  } else {
    // Placed now so that every override is checked against the nodes it will
    // apply to; placed again below, once the channel settings are known.
    s.nodes = scenario::default_formation(o.nodes.value_or(6), s.channel);
    s.name = "default-formation";
  }
  refuse_both_ticks(o);
  for (const auto& setting : o.settings) {
    scenario::apply_setting(s, setting.key, setting.value, origin_of(setting));
  }
  for (const auto& f : o.follow) follow_source(s, *f.source, f.value);
  if (formation) s.nodes = scenario::default_formation(s.nodes.size(), s.channel);
  if (o.transceivers) {
    // Every built-in transceiver moves: inline = in the emulator, child = one
    // `rfsitl node` process each. External programs stay what they are.
    s.phy.process = *o.transceivers;
    for (auto& n : s.nodes) {
      if (n.phy) n.phy->process = *o.transceivers;
    }
  }
  scenario::validate_scenario(s);
  return s;
}

std::string run_fingerprint(const SessionOptions& o) {
  std::string text;
  if (!o.scenario_path.empty()) {
    std::ifstream in(o.scenario_path, std::ios::binary);
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const auto add = [&text](const std::string& v) { text += '\0' + v; };
  if (o.scenario) add(o.scenario->name + "/" + std::to_string(o.scenario->nodes.size()));
  add(std::to_string(o.nodes.value_or(0)));
  for (const auto& s : o.settings) add(s.key + "=" + s.value);
  for (const auto& f : o.follow) add(f.source->info.name + "=" + f.value);
  add(o.transceivers ? std::string(scenario::process_name(*o.transceivers)) : "-");
  return text;
}

}  // namespace rfsitl::session
