#include "rfsitl/phy/phy_registry.hpp"

#include <functional>
#include <map>
#include <stdexcept>

#include "rfsitl/phy/dsss/dsss_transceiver.hpp"
#include "rfsitl/phy/gmsk/fast_gmsk_transceiver.hpp"
#include "rfsitl/phy/gmsk_transceiver.hpp"
#include "rfsitl/phy/ofdm_transceiver.hpp"

namespace rfsitl::phy {
namespace {

using Factory = std::function<std::unique_ptr<Transceiver>(const scenario::PhyConfig&)>;

const std::map<std::string, Factory>& registry() {
  static const std::map<std::string, Factory> factories = {
      // Our own GMSK (fast receiver, ~5 dB more sensitive than liquid-dsp's).
      {"gmsk",
       [](const scenario::PhyConfig& c) {
         return make_fast_gmsk_transceiver(FastGmskSettings{
             c.samples_per_symbol, c.bandwidth_time, c.filter_delay_symbols, c.max_payload_bytes});
       }},
      // liquid-dsp's gmskframegen/gmskframesync, the reference implementation.
      {"gmsk-liquid",
       [](const scenario::PhyConfig& c) {
         return make_gmsk_transceiver(GmskSettings{c.samples_per_symbol, c.filter_delay_symbols,
                                                   c.bandwidth_time, c.max_payload_bytes});
       }},
      {"dsss",
       [](const scenario::PhyConfig& c) {
         return make_dsss_transceiver(DsssSettings{c.code, c.modulation, c.samples_per_chip,
                                                   c.max_payload_bytes, c.adaptive});
       }},
      {"ofdm",
       [](const scenario::PhyConfig& c) {
         return make_ofdm_transceiver(OfdmSettings{c.rate_mbps, c.max_payload_bytes});
       }},
  };
  return factories;
}

}  // namespace

std::unique_ptr<Transceiver> make_transceiver(const scenario::PhyConfig& config) {
  const auto it = registry().find(config.type);
  if (it == registry().end()) {
    std::string known;
    for (const auto& name : known_phy_types()) known += (known.empty() ? "" : ", ") + name;
    throw std::invalid_argument("unknown phy type '" + config.type + "' (known: " + known + ")");
  }
  return it->second(config);
}

std::vector<std::string> known_phy_types() {
  std::vector<std::string> names;
  for (const auto& [name, factory] : registry()) names.push_back(name);
  return names;
}

}  // namespace rfsitl::phy
