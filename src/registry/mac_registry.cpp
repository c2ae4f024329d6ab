#include "rfsitl/registry/mac_registry.hpp"

namespace rfsitl::mac {

void register_builtin(registry::Registry<MacComponent>& r);  // generated from the component folders

registry::Registry<MacComponent>& mac_registry() {
  static registry::Registry<MacComponent> r = registry::with_builtins<MacComponent>();
  return r;
}

const registry::Registry<MacComponent>::List& mac_components() {
  return mac_registry().all();
}

const MacComponent* find_mac(std::string_view name) {
  return mac_registry().find(name);
}

}  // namespace rfsitl::mac
