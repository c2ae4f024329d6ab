#include "rfsitl/registry/mobility_registry.hpp"

namespace rfsitl::position::mobility {

void register_builtin(
    registry::Registry<MobilityComponent>& r);  // generated from the component folders

registry::Registry<MobilityComponent>& mobility_registry() {
  static registry::Registry<MobilityComponent> r = registry::with_builtins<MobilityComponent>();
  return r;
}

const registry::Registry<MobilityComponent>::List& mobility_components() {
  return mobility_registry().all();
}

const MobilityComponent* find_mobility(std::string_view name) {
  return mobility_registry().find(name);
}

}  // namespace rfsitl::position::mobility
