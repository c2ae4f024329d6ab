#pragma once
/// PHY settings as JSON: how the emulator tells an `rfsitl node` process which
/// transceiver to build.
#include <string>

#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::external {

std::string phy_config_to_json(const scenario::PhyConfig& phy);

/// Throws std::invalid_argument naming the field that is missing or mistyped.
scenario::PhyConfig phy_config_from_json(const std::string& json);

}  // namespace rfsitl::external
