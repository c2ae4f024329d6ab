#pragma once
/// MACs by name, as a scenario's `mac: {type: NAME, ...}` selects them.
#include <string_view>
#include <vector>

#include "rfsitl/mac/mac.hpp"

namespace rfsitl::mac {

/// Every registered MAC, sorted by name. Thread-safe.
const std::vector<MacComponent>& mac_components();

/// The MAC named `name`, or nullptr.
const MacComponent* find_mac(std::string_view name);

}  // namespace rfsitl::mac
