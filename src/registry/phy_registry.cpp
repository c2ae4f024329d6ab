#include "rfsitl/registry/phy_registry.hpp"

#include <algorithm>
#include <stdexcept>

namespace rfsitl::phy {

void register_builtin(registry::Registry<PhyComponent>& r);  // generated from the component folders

registry::Registry<PhyComponent>& phy_registry() {
  // A built-in PHY must say how large a frame it carries (the engine sizes
  // queues and MACs from it) and its PER curve (every estimate of a link's
  // PER, `rfsitl links`, needs the receiver's).
  static registry::Registry<PhyComponent> r =
      registry::with_builtins<PhyComponent>([](const PhyComponent& p) {
        if (p.kind != TransceiverKind::kBuiltIn) return;
        if (p.info.find(kMaxPayloadSetting) == nullptr) {
          throw std::invalid_argument("PHY " + p.info.name + " does not declare " +
                                      std::string(kMaxPayloadSetting));
        }
        if (!p.per_curve) {
          throw std::invalid_argument("PHY " + p.info.name + " does not declare its PER curve");
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

namespace {

/// The registered PHY `type` after checking `settings` against its
/// declaration; throws std::invalid_argument naming what is wrong.
const PhyComponent& checked_phy(std::string_view type, const config::Settings& settings) {
  const PhyComponent* p = find_phy(type);
  if (p == nullptr) {
    std::string known;
    for (const auto& name : known_phy_types()) known += (known.empty() ? "" : ", ") + name;
    throw std::invalid_argument("unknown phy type '" + std::string(type) + "' (known: " + known +
                                ")");
  }
  try {
    p->info.validate(settings);
  } catch (const config::SettingError& e) {
    throw std::invalid_argument("phy " + std::string(type) + ": " + e.key() + ": " + e.what());
  }
  return *p;
}

}  // namespace

std::unique_ptr<Transceiver> make_transceiver(std::string_view type,
                                              const config::Settings& settings) {
  const PhyComponent& p = checked_phy(type, settings);
  if (!p.make) {
    throw std::invalid_argument("phy type '" + std::string(type) +
                                "' is another program's transceiver; rfsitl cannot build it");
  }
  return p.make(settings);
}

PerCurve declared_per_curve(std::string_view type, const config::Settings& settings) {
  const PhyComponent& p = checked_phy(type, settings);
  return p.per_curve ? p.per_curve(settings) : PerCurve{};
}

std::unique_ptr<Transceiver> make_transceiver(std::string_view type) {
  const PhyComponent* p = find_phy(type);
  return make_transceiver(type, p != nullptr ? p->info.defaults() : config::Settings{});
}

}  // namespace rfsitl::phy
