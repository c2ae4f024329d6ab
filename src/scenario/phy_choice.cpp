#include <stdexcept>

#include "rfsitl/config/setting.hpp"
#include "rfsitl/registry/phy_registry.hpp"
#include "rfsitl/scenario/scenario.hpp"

namespace rfsitl::scenario {

std::string_view process_name(Process p) {
  return p == Process::kChild ? "child" : "inline";
}

config::Settings PhyChoice::phy_defaults(std::string_view type) {
  const phy::PhyComponent* c = phy::find_phy(type);
  return c != nullptr ? c->info.defaults() : config::Settings{};
}

const phy::PhyComponent& PhyChoice::component() const {
  const phy::PhyComponent* c = phy::find_phy(type);
  if (c == nullptr) throw std::logic_error("phy type '" + type + "' is not registered");
  return *c;
}

bool PhyChoice::external_program() const {
  return component().kind == phy::TransceiverKind::kExternalProgram;
}

bool PhyChoice::runs_externally() const {
  return external_program() || process == Process::kChild;
}

std::size_t PhyChoice::max_payload_bytes() const {
  const config::Value* v = settings.find(phy::kMaxPayloadSetting);
  return v != nullptr ? static_cast<std::size_t>(std::get<std::uint64_t>(*v)) : 0;
}

std::string PhyChoice::label() const {
  const phy::PhyComponent& c = component();
  std::string out;
  if (c.label) {
    out = c.label(settings);
  } else {
    // The type and whatever differs from its defaults.
    out = type;
    const config::Settings defaults = c.info.defaults();
    for (const auto& [key, value] : settings) {
      const config::Value* d = defaults.find(key);
      if (d == nullptr || *d != value) out += " " + key + "=" + config::to_text(value);
    }
  }
  return process == Process::kChild && !external_program() ? out + " [child]" : out;
}

}  // namespace rfsitl::scenario
