#include "rfsitl/registry/position_source_registry.hpp"

namespace rfsitl::position {

void register_builtin(
    registry::Registry<PositionSourceComponent>& r);  // generated from the component folders

registry::Registry<PositionSourceComponent>& position_source_registry() {
  static registry::Registry<PositionSourceComponent> r =
      registry::with_builtins<PositionSourceComponent>();
  return r;
}

const registry::Registry<PositionSourceComponent>::List& position_source_components() {
  return position_source_registry().all();
}

const PositionSourceComponent* find_position_source(std::string_view name) {
  return position_source_registry().find(name);
}

}  // namespace rfsitl::position
