#pragma once
/// Live position sources by name ("mavlink"), as the scenario's
/// `position: {source: NAME, ...}` selects them.
/// Built-ins register on first use; plugins add theirs at start
/// (registry.hpp says when each may be called, from which thread).
#include <string_view>

#include "rfsitl/position/source/position_source.hpp"
#include "rfsitl/registry/registry.hpp"

namespace rfsitl::position {

/// The registry itself, for registering (plugins) and for generic readers.
registry::Registry<PositionSourceComponent>& position_source_registry();

/// Every registered source, sorted by name.
const registry::Registry<PositionSourceComponent>::List& position_source_components();

/// The one named `name`, or nullptr.
const PositionSourceComponent* find_position_source(std::string_view name);

}  // namespace rfsitl::position
