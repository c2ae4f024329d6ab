#include "rfsitl/external/phy_config_json.hpp"

#include <stdexcept>

#include <nlohmann/json.hpp>

#include "rfsitl/config/settings_json.hpp"
#include "rfsitl/registry/phy_registry.hpp"

namespace rfsitl::external {

std::string phy_to_json(std::string_view type, const config::Settings& settings) {
  return nlohmann::json{{"type", type}, {"settings", config::to_json(settings)}}.dump();
}

PhyRequest phy_from_json(const std::string& json) {
  PhyRequest r;
  try {
    const auto j = nlohmann::json::parse(json);
    j.at("type").get_to(r.type);
    const phy::PhyComponent* p = phy::find_phy(r.type);
    if (p == nullptr || p->kind != phy::TransceiverKind::kBuiltIn) {
      throw std::invalid_argument("PHY settings JSON: type '" + r.type +
                                  "' is not a built-in PHY of this rfsitl");
    }
    r.settings = config::settings_from_json(p->info, j.at("settings"));
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument(std::string("PHY settings JSON: ") + e.what());
  } catch (const config::SettingError& e) {
    throw std::invalid_argument("PHY settings JSON: " + r.type + "." + e.key() + ": " + e.what());
  }
  return r;
}

}  // namespace rfsitl::external
