#include "rfsitl/registry/phy_registry.hpp"

#include <algorithm>
#include <stdexcept>

// The built-in PHYs, one entry each: adding a PHY is a folder under src/phy/
// (with a CMakeLists.txt building rfsitl_<folder>) that defines
// `PhyComponent <folder>_component()`, and the folder's name here.
#define RFSITL_PHYS(X) X(gmsk) X(gmsk_liquid) X(ofdm) X(dsss) X(gfsk) X(external_program)

namespace rfsitl::phy {

#define RFSITL_DECLARE_PHY(name) PhyComponent name##_component();
RFSITL_PHYS(RFSITL_DECLARE_PHY)
#undef RFSITL_DECLARE_PHY

const std::vector<PhyComponent>& phy_components() {
  static const std::vector<PhyComponent> all = [] {
#define RFSITL_LIST_PHY(name) name##_component(),
    std::vector<PhyComponent> v{RFSITL_PHYS(RFSITL_LIST_PHY)};
#undef RFSITL_LIST_PHY
    std::sort(v.begin(), v.end(), [](const PhyComponent& a, const PhyComponent& b) {
      return a.info.name < b.info.name;
    });
    for (const PhyComponent& p : v) {
      if (p.kind == TransceiverKind::kBuiltIn && p.info.find(kMaxPayloadSetting) == nullptr) {
        throw std::logic_error("PHY " + p.info.name + " does not declare max_payload_bytes");
      }
      // Every estimate of a link's PER (`rfsitl links`) needs the receiver's curve.
      if (p.kind == TransceiverKind::kBuiltIn && !p.per_curve) {
        throw std::logic_error("PHY " + p.info.name + " does not declare its PER curve");
      }
    }
    return v;
  }();
  return all;
}

const PhyComponent* find_phy(std::string_view type) {
  const auto& all = phy_components();
  const auto it = std::find_if(all.begin(), all.end(),
                               [type](const PhyComponent& p) { return p.info.name == type; });
  return it == all.end() ? nullptr : &*it;
}

std::vector<std::string> known_phy_types() {
  std::vector<std::string> names;
  for (const PhyComponent& p : phy_components()) names.push_back(p.info.name);
  return names;
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
