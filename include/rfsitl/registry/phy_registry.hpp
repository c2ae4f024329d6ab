#pragma once
/// Transceivers are chosen by name in the scenario ("gmsk", ...). The engine,
/// the scenario reader and `rfsitl describe` find them here and never name a
/// concrete class.
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "rfsitl/phy/phy_component.hpp"
#include "rfsitl/registry/registry.hpp"

namespace rfsitl::phy {

/// The registry itself, for registering (plugins) and for generic readers.
/// Built-ins register on first use; plugins add theirs at start (registry.hpp
/// says when each may be called, from which thread).
registry::Registry<PhyComponent>& phy_registry();

/// Every registered PHY, sorted by name.
const registry::Registry<PhyComponent>::List& phy_components();

/// The PHY named `type`, or nullptr.
const PhyComponent* find_phy(std::string_view type);

/// The registered names, sorted.
std::vector<std::string> known_phy_types();

/// Builds a transceiver of `type` with `settings` (validated here). Throws
/// std::invalid_argument naming an unknown type (and listing the known ones), a
/// type that is an external program, or the setting at fault.
std::unique_ptr<Transceiver> make_transceiver(std::string_view type,
                                              const config::Settings& settings);

/// The declared PER curve (per_curve.hpp) of a `type` transceiver with
/// `settings` (validated here, as make_transceiver does); an empty function
/// when the PHY declares none (another program's transceiver). Throws as
/// make_transceiver for an unknown type or a bad setting.
PerCurve declared_per_curve(std::string_view type, const config::Settings& settings);

/// `type` with its declared defaults (e.g. for tests and benchmarks).
std::unique_ptr<Transceiver> make_transceiver(std::string_view type);

}  // namespace rfsitl::phy
