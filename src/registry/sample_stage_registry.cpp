#include "rfsitl/registry/sample_stage_registry.hpp"

namespace rfsitl::channel {

void register_builtin(
    registry::Registry<SampleStageComponent>& r);  // generated from the component folders

registry::Registry<SampleStageComponent>& sample_stage_registry() {
  static registry::Registry<SampleStageComponent> r =
      registry::with_builtins<SampleStageComponent>();
  return r;
}

const registry::Registry<SampleStageComponent>::List& sample_stage_components() {
  return sample_stage_registry().all();
}

const SampleStageComponent* find_sample_stage(std::string_view name) {
  return sample_stage_registry().find(name);
}

}  // namespace rfsitl::channel
