// Registration of rfsitl's own GMSK transceiver as PHY "gmsk".
#include "rfsitl/config/fields.hpp"
#include "rfsitl/phy/gmsk/fast_gmsk_transceiver.hpp"
#include "rfsitl/phy/gmsk/frame_format.hpp"
#include "rfsitl/phy/phy_component.hpp"

namespace rfsitl::phy {
namespace {

const config::Fields<FastGmskSettings>& fields() {
  using S = FastGmskSettings;
  static const auto f =
      config::Fields<S>()
          .integer("samples_per_symbol", &S::samples_per_symbol, "samples", 2, 8,
                   "samples per symbol k; the bit rate is fs / k")
          .real("bandwidth_time", &S::bandwidth_time, "", {0.2, 1.0},
                "BT, bandwidth-time product of the Gaussian filter")
          .integer("filter_delay_symbols", &S::filter_span_symbols, "symbols", 1, 8,
                   "length L of the frequency pulse")
          .integer(std::string(kMaxPayloadSetting), &S::max_payload_bytes, "bytes", 1,
                   gmsk::kMaxPayloadBytes, "largest payload of one frame");
  return f;
}

}  // namespace

PhyComponent gmsk_component() {
  return {fields().info("phy", "gmsk",
                        "GMSK, rfsitl's own fast receiver (about 5 dB more sensitive than "
                        "gmsk-liquid)"),
          TransceiverKind::kBuiltIn,
          [](const config::Settings& s) { return make_fast_gmsk_transceiver(fields().build(s)); },
          {}};
}

}  // namespace rfsitl::phy
