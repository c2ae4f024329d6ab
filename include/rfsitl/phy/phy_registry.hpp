#pragma once
/// Transceivers are chosen by name in the scenario ("gmsk", ...). Each PHY
/// registers a factory here; the engine never names a concrete class.
#include <memory>
#include <string>
#include <vector>

#include "rfsitl/phy/transceiver.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::phy {

/// Builds the transceiver `config.type` names. Throws std::invalid_argument
/// naming the unknown type and listing the known ones.
std::unique_ptr<Transceiver> make_transceiver(const scenario::PhyConfig& config);

/// Names accepted by make_transceiver, sorted.
std::vector<std::string> known_phy_types();

}  // namespace rfsitl::phy
