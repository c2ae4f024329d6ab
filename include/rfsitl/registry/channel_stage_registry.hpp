#pragma once
/// Channel stages by name, as a scenario's `channel.stages: [{type: NAME, ...}]`
/// selects them.
#include <string_view>
#include <vector>

#include "rfsitl/channel/channel_stage.hpp"

namespace rfsitl::channel {

/// Every registered stage, sorted by name. Thread-safe.
const std::vector<ChannelStageComponent>& channel_stage_components();

/// The stage named `name`, or nullptr.
const ChannelStageComponent* find_channel_stage(std::string_view name);

}  // namespace rfsitl::channel
