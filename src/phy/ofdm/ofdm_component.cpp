// Registration of the IEEE 802.11a/g OFDM transceiver as PHY "ofdm".
#include "ofdm_transceiver.hpp"
#include "rfsitl/config/fields.hpp"
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
  return {
      fields().info("phy", "ofdm", "IEEE 802.11a/g OFDM (annex I conformant), 6 to 54 Mbit/s"),
      TransceiverKind::kBuiltIn,
      [](const config::Settings& s) { return make_ofdm_transceiver(fields().build(s)); },
      [](const config::Settings& s) {
        return "ofdm " + std::to_string(fields().build(s).rate_mbps) + " Mbit/s";
      },
      [](const config::Settings& s) {
        // Convolutionally coded: no simple closed form, so each rate's
        // measured waterfall (docs/per_vs_snr.csv, 80-byte payloads) as a
        // fitted logistic {50 % SNR, width}, rms error 0.016 to 0.027. The
        // MAC header and FCS (30 bytes) count in the frame's length.
        struct Waterfall {
          unsigned mbps;
          double snr50_db;
          double width_db;
        };
        static constexpr Waterfall kFits[] = {
            {6, 2.0, 0.470},  {9, 2.8, 0.375},   {12, 4.2, 0.560},  {18, 6.3, 0.550},
            {24, 8.8, 0.575}, {36, 12.0, 0.545}, {48, 15.8, 0.560}, {54, 17.3, 0.575}};
        constexpr std::size_t kFitPayloadBytes = 80;
        constexpr std::size_t kMacOverheadBytes = 30;
        const unsigned rate = fields().build(s).rate_mbps;
        const Waterfall* w = &kFits[0];
        for (const Waterfall& f : kFits) {
          if (f.mbps == rate) w = &f;
        }
        return waterfall_per(w->snr50_db, w->width_db, kFitPayloadBytes, kMacOverheadBytes);
      },
      [](const config::Settings&) {
        // The transmit spectrum mask of IEEE 802.11-2020 clause 17.3.9.3
        // for 20 MHz channels: 0 dBr to +-9 MHz, -20 dBr at 11 MHz, -28
        // dBr at 20 MHz, -40 dBr at 30 MHz (and beyond, which the mask
        // ends at: channel/radio_tuning.hpp), in units of the sample rate
        // (20 Msps, the standard's, makes them the standard's MHz).
        return SpectralMask{{{0.0, 0.0}, {0.45, 0.0}, {0.55, -20.0}, {1.0, -28.0}, {1.5, -40.0}}};
      }};
}

}  // namespace rfsitl::phy
