#include "rfsitl/registry/position_source_registry.hpp"

#include <algorithm>

// The live position sources, one entry each: adding one is a folder under
// src/position/ (with a CMakeLists.txt building rfsitl_<folder>) that defines
// `PositionSourceComponent <folder>_component()`, and the folder's name here.
#define RFSITL_POSITION_SOURCES(X) X(location_port) X(mavlink_source)

namespace rfsitl::position {

#define RFSITL_DECLARE_SOURCE(name) PositionSourceComponent name##_component();
RFSITL_POSITION_SOURCES(RFSITL_DECLARE_SOURCE)
#undef RFSITL_DECLARE_SOURCE

const std::vector<PositionSourceComponent>& position_source_components() {
  static const std::vector<PositionSourceComponent> all = [] {
#define RFSITL_LIST_SOURCE(name) name##_component(),
    std::vector<PositionSourceComponent> v{RFSITL_POSITION_SOURCES(RFSITL_LIST_SOURCE)};
#undef RFSITL_LIST_SOURCE
    std::sort(v.begin(), v.end(),
              [](const auto& a, const auto& b) { return a.info.name < b.info.name; });
    return v;
  }();
  return all;
}

const PositionSourceComponent* find_position_source(std::string_view name) {
  const auto& all = position_source_components();
  const auto it = std::find_if(all.begin(), all.end(), [name](const PositionSourceComponent& c) {
    return c.info.name == name;
  });
  return it == all.end() ? nullptr : &*it;
}

}  // namespace rfsitl::position
