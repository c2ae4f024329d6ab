#include "live_sources.hpp"

#include "rfsitl/registry/position_source_registry.hpp"
#include "rfsitl/scenario/scenario_loader.hpp"

namespace rfsitl::app {

LiveSources::LiveSources(const scenario::Scenario& s) : type_of_(s.nodes.size()) {
  std::map<std::string, std::vector<position::SourceNode>> nodes_of;
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    const scenario::PositionSourceChoice choice = s.source_of(i);
    if (choice.is_location_port()) continue;
    type_of_[i] = choice.type;
    nodes_of[choice.type].push_back({i, s.nodes[i].id, choice.settings});
  }
  for (const auto& [type, nodes] : nodes_of) {
    const auto* component = position::find_position_source(type);
    if (component == nullptr) throw std::invalid_argument("unknown position source " + type);
    sources_.emplace(type, component->make(nodes));
  }
}

void LiveSources::start(position::PositionSink& sink) {
  for (auto& [type, source] : sources_) source->start(sink);
}

void LiveSources::stop() {
  for (auto& [type, source] : sources_) source->stop();
}

std::optional<position::SourceStatus> LiveSources::status(std::size_t index) const {
  if (index >= type_of_.size() || type_of_[index].empty()) return std::nullopt;
  const auto& source = sources_.at(type_of_[index]);
  const auto counters = source->counters(index);
  if (!counters) return std::nullopt;
  return position::SourceStatus{type_of_[index], source->where(index), *counters};
}

void follow_mavlink(scenario::Scenario& s, const std::string& endpoint) {
  const auto* mavlink = position::find_position_source("mavlink");
  scenario::PositionSourceChoice p{"mavlink", s.position_source.type == "mavlink"
                                                  ? s.position_source.settings
                                                  : mavlink->info.defaults()};
  p.settings.set("endpoint", endpoint);
  try {
    mavlink->info.validate(p.settings);
  } catch (const config::SettingError& e) {
    throw scenario::ScenarioError("--mavlink: " + std::string(e.what()));
  }
  s.position_source = p;
  for (auto& n : s.nodes) n.source.reset();
}

}  // namespace rfsitl::app
