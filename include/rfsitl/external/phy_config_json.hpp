#pragma once
/// A PHY choice as JSON: how the emulator tells an `rfsitl node` process which
/// transceiver to build. {"type": "ofdm", "settings": {"rate_mbps": 24, ...}},
/// the settings being those the PHY declares (config/settings_json.hpp).
#include <string>
#include <string_view>

#include "rfsitl/config/settings.hpp"

namespace rfsitl::external {

struct PhyRequest {
  std::string type;
  config::Settings settings;
};

std::string phy_to_json(std::string_view type, const config::Settings& settings);

/// Reads and validates a request against the PHY registry. Throws
/// std::invalid_argument naming what is missing, unknown or out of range.
PhyRequest phy_from_json(const std::string& json);

}  // namespace rfsitl::external
