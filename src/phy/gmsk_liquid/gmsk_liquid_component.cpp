// Registration of liquid-dsp's GMSK framing as PHY "gmsk-liquid".
#include "gmsk_transceiver.hpp"
#include "rfsitl/config/fields.hpp"
#include "rfsitl/phy/phy_component.hpp"

namespace rfsitl::phy {
namespace {

const config::Fields<GmskSettings>& fields() {
  using S = GmskSettings;
  static const auto f = config::Fields<S>()
                            .integer("samples_per_symbol", &S::samples_per_symbol, "samples", 2, 16,
                                     "samples per symbol k; the bit rate is fs / k")
                            .real("bandwidth_time", &S::bandwidth_time, "", {0, 1, true, true},
                                  "BT, bandwidth-time product of the Gaussian filter")
                            .integer("filter_delay_symbols", &S::filter_delay_symbols, "symbols", 1,
                                     16, "delay m of liquid's pulse-shaping filter")
                            .integer(std::string(kMaxPayloadSetting), &S::max_payload_bytes,
                                     "bytes", 1, 65535, "largest payload of one frame");
  return f;
}

}  // namespace

PhyComponent gmsk_liquid_component() {
  return {fields().info("phy", "gmsk-liquid",
                        "GMSK with liquid-dsp's gmskframegen/gmskframesync, the reference"),
          TransceiverKind::kBuiltIn,
          [](const config::Settings& s) { return make_gmsk_transceiver(fields().build(s)); },
          {},
          [](const config::Settings& s) {
            // Coherent binary form, alpha = 0.314 fitted to docs/per_vs_snr.csv
            // (k = 2; rms error 0.021, 50 % at 9.0 dB): 5 dB from ideal MSK.
            // 8 header bytes (rfsitl's tag) and liquid's CRC-32.
            constexpr double kAlpha = 0.314;
            constexpr std::size_t kOverheadBytes = 8 + 4;
            return coherent_binary_per(kAlpha, fields().build(s).samples_per_symbol,
                                       kOverheadBytes);
          },
          {}};  // no declared mask: flat over the node's channel (radio_tuning.hpp)
}

}  // namespace rfsitl::phy
