// Registration of the direct-sequence spread-spectrum transceiver as PHY "dsss".
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "code_adaptation.hpp"
#include "codes.hpp"
#include "dsss_transceiver.hpp"
#include "frame_format.hpp"
#include "rfsitl/config/fields.hpp"
#include "rfsitl/phy/phy_component.hpp"

namespace rfsitl::phy {
namespace {

void check_code(const DsssSettings& s) {
  dsss::SpreadingCode code;
  try {
    code = dsss::code_by_name(s.code);
  } catch (const std::invalid_argument& e) {
    throw config::SettingError("code", e.what());
  }
  // Adaptation moves between members of the code's Gold family; a code without
  // one (barker11, mseq255) leaves it nothing to choose from.
  if (s.adaptive && dsss::adaptation_candidates(code, 2).size() < 2) {
    throw config::SettingError("adaptive",
                               "needs a code with a Gold family (mseq<N> or gold<N> with N in "
                               "31, 63, 127, 511, 1023), but code is '" +
                                   s.code + "'");
  }
}

const config::Fields<DsssSettings>& fields() {
  using S = DsssSettings;
  static const auto f =
      config::Fields<S>()
          .text("code", &S::code,
                "spreading code: barker11, mseq<N> (N = 2^n - 1, n = 5..10) or gold<N>[:k] "
                "(N = 31, 63, 127, 511, 1023; k = family member)")
          .choice("modulation", &S::modulation, {"dbpsk", "dqpsk"},
                  "differential BPSK (1 bit per code period) or QPSK (2 bits)")
          .integer("samples_per_chip", &S::samples_per_chip, "samples", 1, 8,
                   "samples per chip; the chip rate is fs / this")
          .integer(std::string(kMaxPayloadSetting), &S::max_payload_bytes, "bytes", 1, 65535,
                   "largest payload of one frame")
          .flag("adaptive", &S::adaptive, "cognitive code adaptation among the code's Gold family")
          .rule(check_code);
  return f;
}

// Rectangular chips of samples_per_chip samples: a density of sinc^2(f Tc),
// nulls at multiples of the chip rate fs / samples_per_chip, sampled in dB
// (floored at -60 dBr, the nulls) up to half the sample rate, the most a
// sampled signal shows.
SpectralMask chip_mask(unsigned samples_per_chip) {
  constexpr int kSteps = 200;
  constexpr double kFloorDbr = -60.0;
  SpectralMask mask;
  for (int i = 0; i <= kSteps; ++i) {
    const double offset = 0.5 * i / kSteps;  // in sample rates
    const double x = std::numbers::pi * offset * samples_per_chip;
    const double sinc = i == 0 ? 1.0 : std::sin(x) / x;
    const double dbr = 10.0 * std::log10(std::max(sinc * sinc, std::pow(10.0, kFloorDbr / 10)));
    mask.points.push_back({offset, dbr});
  }
  return mask;
}

}  // namespace

PhyComponent dsss_component() {
  return {fields().info("phy", "dsss",
                        "direct-sequence spread spectrum with differential PSK and optional "
                        "code adaptation"),
          TransceiverKind::kBuiltIn,
          [](const config::Settings& s) { return make_dsss_transceiver(fields().build(s)); },
          [](const config::Settings& s) {
            const DsssSettings d = fields().build(s);
            return "dsss " + d.code + " " + d.modulation + (d.adaptive ? " adaptive" : "");
          },
          [](const config::Settings& s) {
            // Differential detection after despreading: BER = 0.5 exp(-beta
            // Eb/N0) with Eb/N0 = SNR (chips per code period) (samples per chip)
            // / (bits per period): the processing gain. DBPSK is the textbook
            // beta = 1 (the fits to docs/per_vs_snr.csv give 1.03 to 1.04 for
            // barker11, mseq31 and mseq127); DQPSK's 0.773 is fitted (barker11,
            // rms error 0.038).
            const DsssSettings d = fields().build(s);
            const bool dqpsk = d.modulation == "dqpsk";
            const double samples_per_bit =
                static_cast<double>(dsss::code_by_name(d.code).chips.size() * d.samples_per_chip) /
                (dqpsk ? 2.0 : 1.0);
            return exponential_binary_per(dqpsk ? 0.773 : 1.0, samples_per_bit,
                                          dsss::kHeaderBytes + dsss::kCrc32Bytes);
          },
          [](const config::Settings& s) { return chip_mask(fields().build(s).samples_per_chip); }};
}

}  // namespace rfsitl::phy
