#include "rfsitl/external/external_runtime.hpp"

#include <cmath>

#include "rfsitl/external/external_transceivers.hpp"
#include "rfsitl/external/phy_config_json.hpp"
#include "rfsitl/registry/phy_registry.hpp"

namespace rfsitl::external {

std::string external_socket_path(const scenario::Scenario& s) {
  if (!s.external.socket_path.empty()) return s.external.socket_path;
  return "/tmp/rfsitl-" + std::to_string(s.ports.net_base) + ".sock";
}

ExternalRuntime::ExternalRuntime(const scenario::Scenario& s, const ExternalPlacement& placement)
    : scenario_(s) {
  const auto here = [&](std::size_t i) {
    return placement.here.empty() || (i < placement.here.size() && placement.here[i]);
  };
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    if (!s.runs_externally(i) || !here(i)) continue;
    const scenario::PhyChoice& phy = s.phy_of(i);
    const bool samples = phy.external_program();
    specs_.push_back(
        ExternalNodeSpec{i, s.nodes[i].id, samples ? Role::kSamples : Role::kTransceiver,
                         samples ? std::string() : phy_to_json(phy.type, phy.settings)});
  }
  if (specs_.empty()) return;  // every external node is served elsewhere
  HubSettings hs;
  hs.socket_path = placement.socket_path.empty() ? external_socket_path(s) : placement.socket_path;
  // validate() bounds reply_timeout_s to (0, 3600], so the cast is defined.
  hs.reply_timeout_ms = static_cast<int>(std::ceil(s.external.reply_timeout_s * 1e3));
  hs.sample_rate_hz = s.timing.sample_rate_hz;
  hs.tick_samples = s.timing.tick_samples;
  hs.virtual_time = s.timing.mode == scenario::TimeMode::kVirtual;
  hs.scenario_name = s.name;
  // The channel's own default when the scenario has no radio: section.
  hs.carrier_hz = s.radio.value_or(channel::RadioSettings{}).carrier_hz;
  hub_ = make_external_hub(hs, specs_);
}

std::unique_ptr<ExternalRuntime> ExternalRuntime::create(const scenario::Scenario& s,
                                                         ExternalPlacement placement) {
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    if (s.runs_externally(i)) {
      return std::unique_ptr<ExternalRuntime>(new ExternalRuntime(s, placement));
    }
  }
  return nullptr;
}

engine::TransceiverFactory ExternalRuntime::transceiver_factory() const {
  return [this](std::size_t index, const scenario::PhyChoice& phy,
                engine::NodeCounters& counters) -> std::unique_ptr<phy::Transceiver> {
    const auto link = hub_ ? hub_->link(index) : nullptr;
    if (!link) {
      // Not served here: a built-in PHY, or an external node of another rank,
      // whose transceiver this process only asks for its figures (for a
      // program's samples those of the proxy; for a PHY in another process,
      // the PHY's own, as the proxy's shadow gives them).
      if (phy.external_program()) return make_sample_port_stand_in();
      return phy::make_transceiver(phy.type, phy.settings);
    }
    link->count_stalls_in(counters.external_stalls);
    if (phy.external_program()) {
      return make_sample_port_transceiver(link, scenario_.timing.tick_samples,
                                          counters.external_overflows);
    }
    return make_remote_transceiver(link, phy);
  };
}

void ExternalRuntime::start_children() {
  if (!hub_) return;
  ChildSettings cs;
  cs.executable = current_executable();
  cs.socket_path = hub_->socket_path();
  cs.restart = scenario_.external.restart_children;
  for (const auto& spec : specs_) {
    if (spec.role == Role::kTransceiver) cs.node_ids.push_back(spec.id);
  }
  if (!cs.node_ids.empty()) children_ = start_children_of(cs);
}

nlohmann::json ExternalRuntime::summary() const {
  nlohmann::json j = nlohmann::json::object();
  j["nodes"] = nlohmann::json::array();
  if (!hub_) {
    j["socket"] = nullptr;
    j["rejected_connections"] = 0;
    j["child_restarts"] = 0;
    return j;
  }
  j["socket"] = hub_->socket_path();
  j["rejected_connections"] = hub_->rejected();
  j["child_restarts"] = child_restarts();
  for (const auto& spec : specs_) {
    const auto link = hub_->link(spec.index);
    j["nodes"].push_back({{"id", spec.id},
                          {"role", role_name(spec.role)},
                          {"joins", link->joins()},
                          {"drops", link->drops()},
                          {"timeouts", link->timeouts()}});
  }
  return j;
}

}  // namespace rfsitl::external
