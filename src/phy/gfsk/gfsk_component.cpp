// Registration of the 2-GFSK transceiver as PHY "gfsk".
#include <string>

#include "gfsk_frame.hpp"
#include "gfsk_transceiver.hpp"
#include "rfsitl/config/fields.hpp"
#include "rfsitl/phy/phy_component.hpp"

namespace rfsitl::phy {
namespace {

void check_combination(const GfskSettings& s) {
  if (s.bandwidth_time != 0.0F && s.bandwidth_time < 0.2F) {
    throw config::SettingError("bandwidth_time", "must be 0 (no shaping) or in [0.2, 1], got " +
                                                     config::to_text(double{s.bandwidth_time}));
  }
  // Carson's bandwidth (h + 1) Rb must fit in the sample rate k Rb.
  if (s.modulation_index > static_cast<float>(s.samples_per_symbol) - 1.0F) {
    throw config::SettingError(
        "modulation_index",
        "must be at most samples_per_symbol - 1 = " + std::to_string(s.samples_per_symbol - 1) +
            " (the tones must fit in the sample rate), got " +
            config::to_text(double{s.modulation_index}));
  }
}

const config::Fields<GfskSettings>& fields() {
  using S = GfskSettings;
  static const auto f =
      config::Fields<S>()
          .integer("samples_per_symbol", &S::samples_per_symbol, "samples", 2, 32,
                   "samples per bit; the air rate is fs / this (8: 125 kbit/s at 1 Msps)")
          .real("modulation_index", &S::modulation_index, "", {0, 2, true, false},
                "h = 2 fd / Rb; SiK radios use about 2")
          .real("bandwidth_time", &S::bandwidth_time, "", {0, 1},
                "BT of the Gaussian frequency filter; 0 = no shaping (plain FSK)")
          .choice(
              "receiver", &S::receiver,
              {{"discriminator", GfskReceiver::kDiscriminator}, {"energy", GfskReceiver::kEnergy}},
              "FM discriminator (SiK-like) or two-tone non-coherent energy detector")
          .flag("whitening", &S::whitening, "PN9 whitening of header and payload")
          .integer("preamble_bytes", &S::preamble_bytes, "bytes", 2, 64,
                   "0xAA octets before the sync word")
          .integer(std::string(kMaxPayloadSetting), &S::max_payload_bytes, "bytes", 1, 65535,
                   "largest payload of one frame (SiK: 255)")
          .rule(check_combination);
  return f;
}

}  // namespace

PhyComponent gfsk_component() {
  return {fields().info("phy", "gfsk",
                        "2-GFSK like the SiK telemetry radios of small UAVs, with a "
                        "discriminator or energy-detector receiver"),
          TransceiverKind::kBuiltIn,
          [](const config::Settings& s) { return make_gfsk_transceiver(fields().build(s)); },
          {},
          [](const config::Settings& s) {
            // Non-coherent binary FSK, BER = 0.5 exp(-beta Eb/N0), Eb/N0 = SNR k.
            // The energy detector is the textbook one (beta = 1/2; the fit to
            // docs/per_vs_snr.csv, h = 1, gives 0.500, rms error 0.012). The
            // discriminator's beta = 0.264 is fitted at SiK's h = 2, BT = 0.5
            // (rms error 0.021, 50 % at 4.8 dB); other h and BT use it too.
            const GfskSettings g = fields().build(s);
            const double beta = g.receiver == GfskReceiver::kEnergy ? 0.5 : 0.264;
            return exponential_binary_per(beta, g.samples_per_symbol,
                                          gfsk::kHeaderBytes + gfsk::kPayloadCrcBytes);
          },
          {}};  // no declared mask: flat over the node's channel (radio_tuning.hpp)
}

}  // namespace rfsitl::phy
