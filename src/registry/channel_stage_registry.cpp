#include "rfsitl/registry/channel_stage_registry.hpp"

namespace rfsitl::channel {

void register_builtin(
    registry::Registry<ChannelStageComponent>& r);  // generated from the component folders

registry::Registry<ChannelStageComponent>& channel_stage_registry() {
  static registry::Registry<ChannelStageComponent> r =
      registry::with_builtins<ChannelStageComponent>();
  return r;
}

const registry::Registry<ChannelStageComponent>::List& channel_stage_components() {
  return channel_stage_registry().all();
}

const ChannelStageComponent* find_channel_stage(std::string_view name) {
  return channel_stage_registry().find(name);
}

}  // namespace rfsitl::channel
