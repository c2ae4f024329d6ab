#pragma once
/// Mobility models by name, as a node's `mobility: {type: NAME, ...}` selects them.
/// Built-ins register on first use; plugins add theirs at start
/// (registry.hpp says when each may be called, from which thread).
#include <string_view>

#include "rfsitl/position/mobility/mobility_component.hpp"
#include "rfsitl/registry/registry.hpp"

namespace rfsitl::position::mobility {

/// The registry itself, for registering (plugins) and for generic readers.
registry::Registry<MobilityComponent>& mobility_registry();

/// Every registered model, sorted by name.
const registry::Registry<MobilityComponent>::List& mobility_components();

/// The one named `name`, or nullptr.
const MobilityComponent* find_mobility(std::string_view name);

}  // namespace rfsitl::position::mobility
