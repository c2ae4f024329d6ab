#include "rfsitl/registry/mac_registry.hpp"

#include <algorithm>

// The MACs, one entry each: adding one is a folder under src/mac/ (with a
// CMakeLists.txt building rfsitl_mac_<folder>) that defines
// `MacComponent <folder>_component()`, and the folder's name here.
#define RFSITL_MACS(X) X(none) X(csma) X(tdma)

namespace rfsitl::mac {

#define RFSITL_DECLARE_MAC(name) MacComponent name##_component();
RFSITL_MACS(RFSITL_DECLARE_MAC)
#undef RFSITL_DECLARE_MAC

const std::vector<MacComponent>& mac_components() {
  static const std::vector<MacComponent> all = [] {
#define RFSITL_LIST_MAC(name) name##_component(),
    std::vector<MacComponent> v{RFSITL_MACS(RFSITL_LIST_MAC)};
#undef RFSITL_LIST_MAC
    std::sort(v.begin(), v.end(),
              [](const auto& a, const auto& b) { return a.info.name < b.info.name; });
    return v;
  }();
  return all;
}

const MacComponent* find_mac(std::string_view name) {
  const auto& all = mac_components();
  const auto it = std::find_if(all.begin(), all.end(),
                               [name](const MacComponent& c) { return c.info.name == name; });
  return it == all.end() ? nullptr : &*it;
}

}  // namespace rfsitl::mac
