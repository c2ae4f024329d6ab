#pragma once
/// Channel stages by name, as a scenario's `channel.stages: [{type: NAME, ...}]`
/// selects them.
/// Built-ins register on first use; plugins add theirs at start
/// (registry.hpp says when each may be called, from which thread).
#include <string_view>

#include "rfsitl/channel/channel_stage.hpp"
#include "rfsitl/registry/registry.hpp"

namespace rfsitl::channel {

/// The registry itself, for registering (plugins) and for generic readers.
registry::Registry<ChannelStageComponent>& channel_stage_registry();

/// Every registered stage, sorted by name.
const registry::Registry<ChannelStageComponent>::List& channel_stage_components();

/// The one named `name`, or nullptr.
const ChannelStageComponent* find_channel_stage(std::string_view name);

}  // namespace rfsitl::channel
