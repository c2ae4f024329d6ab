#include "rfsitl/external/phy_config_json.hpp"

#include <stdexcept>

#include <nlohmann/json.hpp>

namespace rfsitl::external {

std::string phy_config_to_json(const scenario::PhyConfig& p) {
  const nlohmann::json j = {{"type", p.type},
                            {"rate_mbps", p.rate_mbps},
                            {"code", p.code},
                            {"modulation", p.modulation},
                            {"samples_per_chip", p.samples_per_chip},
                            {"adaptive", p.adaptive},
                            {"samples_per_symbol", p.samples_per_symbol},
                            {"filter_delay_symbols", p.filter_delay_symbols},
                            {"bandwidth_time", p.bandwidth_time},
                            {"max_payload_bytes", p.max_payload_bytes},
                            {"tx_queue_frames", p.tx_queue_frames}};
  return j.dump();
}

scenario::PhyConfig phy_config_from_json(const std::string& json) {
  scenario::PhyConfig p;
  try {
    const auto j = nlohmann::json::parse(json);
    j.at("type").get_to(p.type);
    j.at("rate_mbps").get_to(p.rate_mbps);
    j.at("code").get_to(p.code);
    j.at("modulation").get_to(p.modulation);
    j.at("samples_per_chip").get_to(p.samples_per_chip);
    j.at("adaptive").get_to(p.adaptive);
    j.at("samples_per_symbol").get_to(p.samples_per_symbol);
    j.at("filter_delay_symbols").get_to(p.filter_delay_symbols);
    j.at("bandwidth_time").get_to(p.bandwidth_time);
    j.at("max_payload_bytes").get_to(p.max_payload_bytes);
    j.at("tx_queue_frames").get_to(p.tx_queue_frames);
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument(std::string("PHY settings JSON: ") + e.what());
  }
  return p;
}

}  // namespace rfsitl::external
