#include "rfsitl/session/live_sources.hpp"

#include "rfsitl/registry/position_source_registry.hpp"
#include "rfsitl/scenario/scenario_loader.hpp"

namespace rfsitl::session {

namespace {
constexpr const char* kLocationPort = scenario::PositionSourceChoice::kLocationPort;
}

LiveSources::LiveSources(const scenario::Scenario& s, const position::SourceContext& context,
                         std::vector<bool> here)
    : type_of_(s.nodes.size()), here_(std::move(here)) {
  if (here_.empty()) here_.assign(s.nodes.size(), true);
  std::map<std::string, std::vector<position::SourceNode>> nodes_of;
  const auto* location_port = position::find_position_source(kLocationPort);
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    const scenario::PositionSourceChoice choice = s.source_of(i);
    type_of_[i] = s.nodes[i].mobility ? "mobility" : choice.type;
    if (!here_[i]) continue;
    // Every node's location port listens; with its own settings where the node
    // chose it.
    nodes_of[kLocationPort].push_back(
        {i, s.nodes[i].id,
         choice.type == kLocationPort ? choice.settings : location_port->info.defaults()});
    if (choice.type != kLocationPort) {
      nodes_of[choice.type].push_back({i, s.nodes[i].id, choice.settings});
    }
  }
  for (const auto& [type, nodes] : nodes_of) {
    const auto* component = position::find_position_source(type);
    if (component == nullptr) throw std::invalid_argument("unknown position source " + type);
    sources_.emplace(type, component->make(context, nodes));
  }
}

void LiveSources::start(position::PositionSink& sink) {
  try {
    for (auto& [type, source] : sources_) source->start(sink);
  } catch (...) {
    stop();
    throw;
  }
}

void LiveSources::stop() {
  for (auto& [type, source] : sources_) source->stop();
}

std::optional<position::SourceStatus> LiveSources::status(std::size_t index) const {
  if (index >= type_of_.size() || !here_[index]) return std::nullopt;
  const std::string& type = type_of_[index];
  const auto& port = *sources_.at(kLocationPort);
  if (type == kLocationPort) {
    return position::SourceStatus{type, port.where(index), *port.counters(index), std::nullopt};
  }
  position::SourceStatus st{type, "", {}, port.counters(index)};
  if (const auto it = sources_.find(type); it != sources_.end()) {
    st.where = it->second->where(index);
    st.counters = it->second->counters(index).value_or(position::SourceCounters{});
  }
  return st;
}

std::string LiveSources::location_port(std::size_t index) const {
  if (!here_[index]) return "another rank's";
  return sources_.at(kLocationPort)->where(index);
}

void follow_source(scenario::Scenario& s, const position::PositionSourceComponent& source,
                   const std::string& value) {
  const std::string& name = source.info.name;
  const std::string& flag = source.flag.flag;
  scenario::PositionSourceChoice p{
      name, s.position_source.type == name ? s.position_source.settings : source.info.defaults()};
  p.settings.set(source.flag.setting, value);
  try {
    source.info.validate(p.settings);
  } catch (const config::SettingError& e) {
    throw scenario::ScenarioError(flag + ": " + std::string(e.what()));
  }
  // Said here, naming the flag, rather than by validate_scenario() as a
  // problem of the scenario's position.source, which the user never wrote.
  if (source.wall_clock && s.timing.mode == scenario::TimeMode::kVirtual) {
    throw scenario::ScenarioError(flag + ": " + scenario::wall_clock_conflict(s.timing));
  }
  s.position_source = p;
  for (auto& n : s.nodes) n.source.reset();
}

}  // namespace rfsitl::session
