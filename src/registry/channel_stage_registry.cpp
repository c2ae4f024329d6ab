#include "rfsitl/registry/channel_stage_registry.hpp"

#include <algorithm>

// The channel stages, one entry each: adding one is a folder under
// src/channel/stages/ (with a CMakeLists.txt building rfsitl_stage_<folder>)
// that defines `ChannelStageComponent <folder>_component()`, and the folder's
// name here.
#define RFSITL_CHANNEL_STAGES(X) \
  X(path_loss) X(shadowing) X(fading) X(antenna) X(occlusion) X(trace) X(delay) X(multipath)

namespace rfsitl::channel {

#define RFSITL_DECLARE_STAGE(name) ChannelStageComponent name##_component();
RFSITL_CHANNEL_STAGES(RFSITL_DECLARE_STAGE)
#undef RFSITL_DECLARE_STAGE

const std::vector<ChannelStageComponent>& channel_stage_components() {
  static const std::vector<ChannelStageComponent> all = [] {
#define RFSITL_LIST_STAGE(name) name##_component(),
    std::vector<ChannelStageComponent> v{RFSITL_CHANNEL_STAGES(RFSITL_LIST_STAGE)};
#undef RFSITL_LIST_STAGE
    std::sort(v.begin(), v.end(),
              [](const auto& a, const auto& b) { return a.info.name < b.info.name; });
    return v;
  }();
  return all;
}

const ChannelStageComponent* find_channel_stage(std::string_view name) {
  const auto& all = channel_stage_components();
  const auto it = std::find_if(all.begin(), all.end(), [name](const ChannelStageComponent& c) {
    return c.info.name == name;
  });
  return it == all.end() ? nullptr : &*it;
}

}  // namespace rfsitl::channel
