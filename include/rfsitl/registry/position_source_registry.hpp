#pragma once
/// Live position sources by name ("mavlink"), as the scenario's
/// `position: {source: NAME, ...}` selects them. Mobility models, the other kind
/// of source, are registered in position/mobility/mobility_component.hpp.
#include <string>
#include <string_view>
#include <vector>

#include "rfsitl/position/source/position_source.hpp"

namespace rfsitl::position {

/// Every registered live source, sorted by name. Thread-safe.
const std::vector<PositionSourceComponent>& position_source_components();

/// The source named `name`, or nullptr.
const PositionSourceComponent* find_position_source(std::string_view name);

}  // namespace rfsitl::position
