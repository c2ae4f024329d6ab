#pragma once
/// Sample stages by name, as a scenario's `channel.tx_stages` and
/// `channel.rx_stages: [{type: NAME, ...}]` select them.
/// Built-ins register on first use; plugins add theirs at start
/// (registry.hpp says when each may be called, from which thread).
#include <string_view>

#include "rfsitl/channel/sample_stage.hpp"
#include "rfsitl/registry/registry.hpp"

namespace rfsitl::channel {

/// The registry itself, for registering (plugins) and for generic readers.
registry::Registry<SampleStageComponent>& sample_stage_registry();

/// Every registered sample stage, sorted by name.
const registry::Registry<SampleStageComponent>::List& sample_stage_components();

/// The one named `name`, or nullptr.
const SampleStageComponent* find_sample_stage(std::string_view name);

}  // namespace rfsitl::channel
