#pragma once
/// MACs by name, as a scenario's `mac: {type: NAME, ...}` selects them.
/// Built-ins register on first use; plugins add theirs at start
/// (registry.hpp says when each may be called, from which thread).
#include <string_view>

#include "rfsitl/mac/mac.hpp"
#include "rfsitl/registry/registry.hpp"

namespace rfsitl::mac {

/// The registry itself, for registering (plugins) and for generic readers.
registry::Registry<MacComponent>& mac_registry();

/// Every registered MAC, sorted by name.
const registry::Registry<MacComponent>::List& mac_components();

/// The one named `name`, or nullptr.
const MacComponent* find_mac(std::string_view name);

}  // namespace rfsitl::mac
