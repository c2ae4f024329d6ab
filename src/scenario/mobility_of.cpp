#include "rfsitl/scenario/mobility_of.hpp"

#include <stdexcept>
#include <utility>
#include <variant>

#include "rfsitl/position/mobility/mobility_component.hpp"
#include "rfsitl/registry/mobility_registry.hpp"

namespace rfsitl::scenario {

std::unique_ptr<position::mobility::MobilityModel> make_mobility(
    const Scenario& s, std::size_t i, std::function<void(const std::string&)> warn) {
  const MobilityChoice& m = *s.nodes[i].mobility;
  const auto* component = position::mobility::find_mobility(m.type);
  if (component == nullptr) throw std::invalid_argument("unknown mobility model " + m.type);
  position::mobility::MobilityContext context;
  context.node = s.nodes[i].id;
  context.scenario_seed = s.seed;
  context.origin = s.channel.origin;
  if (const auto& p = s.nodes[i].initial_position) {
    if (const auto* local = std::get_if<LocalPosition>(&*p)) context.start = *local;
  }
  context.base_dir = s.source_dir;
  context.warn = std::move(warn);
  return component->make(m.settings, context);
}

}  // namespace rfsitl::scenario
