#include "rfsitl/registry/phy_registry.hpp"

#include <algorithm>
#include <stdexcept>

namespace rfsitl::phy {

void register_builtin(registry::Registry<PhyComponent>& r);  // generated from the component folders

registry::Registry<PhyComponent>& phy_registry() {
  // A built-in PHY must say how large a frame it carries: the engine sizes
  // queues and MACs from it.
  static registry::Registry<PhyComponent> r =
      registry::with_builtins<PhyComponent>([](const PhyComponent& p) {
        if (p.kind == TransceiverKind::kBuiltIn && p.info.find(kMaxPayloadSetting) == nullptr) {
          throw std::invalid_argument("PHY " + p.info.name + " does not declare " +
                                      std::string(kMaxPayloadSetting));
        }
      });
  return r;
}

const registry::Registry<PhyComponent>::List& phy_components() {
  return phy_registry().all();
}

const PhyComponent* find_phy(std::string_view type) {
  return phy_registry().find(type);
}

std::vector<std::string> known_phy_types() {
  return phy_registry().names();
}

std::unique_ptr<Transceiver> make_transceiver(std::string_view type,
                                              const config::Settings& settings) {
  const PhyComponent* p = find_phy(type);
  if (p == nullptr) {
    std::string known;
    for (const auto& name : known_phy_types()) known += (known.empty() ? "" : ", ") + name;
    throw std::invalid_argument("unknown phy type '" + std::string(type) + "' (known: " + known +
                                ")");
  }
  if (!p->make) {
    throw std::invalid_argument("phy type '" + std::string(type) +
                                "' is another program's transceiver; rfsitl cannot build it");
  }
  try {
    p->info.validate(settings);
  } catch (const config::SettingError& e) {
    throw std::invalid_argument("phy " + std::string(type) + ": " + e.key() + ": " + e.what());
  }
  return p->make(settings);
}

std::unique_ptr<Transceiver> make_transceiver(std::string_view type) {
  const PhyComponent* p = find_phy(type);
  return make_transceiver(type, p != nullptr ? p->info.defaults() : config::Settings{});
}

}  // namespace rfsitl::phy
