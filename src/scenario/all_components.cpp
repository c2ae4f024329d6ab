#include "rfsitl/scenario/all_components.hpp"

#include "rfsitl/channel/radio.hpp"
#include "rfsitl/config/settings_json.hpp"
#include "rfsitl/registry/channel_stage_registry.hpp"
#include "rfsitl/registry/mac_registry.hpp"
#include "rfsitl/registry/mobility_registry.hpp"
#include "rfsitl/registry/phy_registry.hpp"
#include "rfsitl/registry/position_source_registry.hpp"
#include "rfsitl/registry/sample_stage_registry.hpp"
#include "rfsitl/scenario/spectrum.hpp"

namespace rfsitl::scenario {

std::vector<const config::ComponentInfo*> all_components() {
  std::vector<const config::ComponentInfo*> out;
  for (const position::PositionSourceComponent& s : position::position_source_components())
    out.push_back(&s.info);
  for (const position::mobility::MobilityComponent& m : position::mobility::mobility_components())
    out.push_back(&m.info);
  for (const phy::PhyComponent& p : phy::phy_components()) out.push_back(&p.info);
  for (const mac::MacComponent& m : mac::mac_components()) out.push_back(&m.info);
  for (const channel::ChannelStageComponent& s : channel::channel_stage_components())
    out.push_back(&s.info);
  for (const channel::SampleStageComponent& s : channel::sample_stage_components())
    out.push_back(&s.info);
  out.push_back(&channel::radio_info());
  out.push_back(&spectrum_info());
  out.push_back(&channel_plan_info());
  out.push_back(&node_tuning_info());
  return out;
}

nlohmann::json all_components_json(std::string_view kind) {
  nlohmann::json all = nlohmann::json::array();
  for (const config::ComponentInfo* c : all_components()) {
    if (kind.empty() || c->kind == kind) all.push_back(config::component_json(*c));
  }
  return all;
}

}  // namespace rfsitl::scenario
