// Registration of the IEEE 802.11a/g OFDM transceiver as PHY "ofdm".
#include "rfsitl/config/fields.hpp"
#include "rfsitl/phy/ofdm/ofdm_transceiver.hpp"
#include "rfsitl/phy/phy_component.hpp"

namespace rfsitl::phy {
namespace {

const config::Fields<OfdmSettings>& fields() {
  using S = OfdmSettings;
  static const auto f =
      config::Fields<S>()
          .integer_choice("rate_mbps", &S::rate_mbps, "Mbit/s", {6, 9, 12, 18, 24, 36, 48, 54},
                          "802.11a/g data rate at 20 MHz (the numerology is scaled to fs)")
          // A PSDU is at most 4095 octets, and the MAC header and FCS take 30 of them.
          .integer(std::string(kMaxPayloadSetting), &S::max_payload_bytes, "bytes", 1, 4095 - 30,
                   "largest payload of one frame");
  return f;
}

}  // namespace

PhyComponent ofdm_component() {
  return {fields().info("phy", "ofdm", "IEEE 802.11a/g OFDM (annex I conformant), 6 to 54 Mbit/s"),
          TransceiverKind::kBuiltIn,
          [](const config::Settings& s) { return make_ofdm_transceiver(fields().build(s)); },
          [](const config::Settings& s) {
            return "ofdm " + std::to_string(fields().build(s).rate_mbps) + " Mbit/s";
          }};
}

}  // namespace rfsitl::phy
