#include "gfsk_transceiver.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "gfsk_frame.hpp"
#include "gfsk_receiver.hpp"
#include "phy/gmsk/cpm_modulator.hpp"
#include "phy/gmsk/cpm_transceiver.hpp"
#include "phy/gmsk/gmsk_pulse.hpp"

namespace rfsitl::phy {
namespace {

/// Per-sample SNR (dB) of 10% PER for 80-byte frames at k = 8, h = 2,
/// BT = 0.5, by receiver (bench/gfsk_per_bench.cpp, 1000 frames per point:
/// 5.93 and 5.94 dB).
constexpr double kSensitivityDiscriminatorDb = 5.9;
constexpr double kSensitivityEnergyDb = 5.9;

void fail(const std::string& field, const std::string& range, const std::string& got) {
  throw std::invalid_argument("GfskSettings." + field + " must be " + range + ", got " + got);
}

const GfskSettings& validated(const GfskSettings& s) {
  if (s.samples_per_symbol < 2 || s.samples_per_symbol > 32) {
    fail("samples_per_symbol", "2..32", std::to_string(s.samples_per_symbol));
  }
  if (!(s.modulation_index > 0.0F && s.modulation_index <= 2.0F)) {
    fail("modulation_index", "in (0, 2]", std::to_string(s.modulation_index));
  }
  if (s.modulation_index + 1.0F > static_cast<float>(s.samples_per_symbol)) {
    fail("modulation_index",
         "at most samples_per_symbol - 1 (Carson's bandwidth within the "
         "sample rate)",
         std::to_string(s.modulation_index));
  }
  if (!(s.bandwidth_time == 0.0F || (s.bandwidth_time >= 0.2F && s.bandwidth_time <= 1.0F))) {
    fail("bandwidth_time", "0 (no shaping) or in [0.2, 1]", std::to_string(s.bandwidth_time));
  }
  if (s.receiver != GfskReceiver::kDiscriminator && s.receiver != GfskReceiver::kEnergy) {
    fail("receiver", "kDiscriminator or kEnergy", std::to_string(static_cast<int>(s.receiver)));
  }
  if (s.preamble_bytes < gfsk::kMinPreambleBytes || s.preamble_bytes > gfsk::kMaxPreambleBytes) {
    fail("preamble_bytes", "2..64", std::to_string(s.preamble_bytes));
  }
  if (s.max_payload_bytes < 1 || s.max_payload_bytes > gfsk::kMaxPayloadBytes) {
    fail("max_payload_bytes", "1..65535", std::to_string(s.max_payload_bytes));
  }
  return s;
}

/// The Gaussian pulse truncated to gaussian_span_symbols(BT), or the
/// rectangular one at BT = 0; the phase computed in double (any h).
gmsk::CpmModulator make_modulator(const GfskSettings& s) {
  const unsigned k = s.samples_per_symbol;
  const float bt = s.bandwidth_time;
  return gmsk::CpmModulator(
      bt > 0.0F
          ? gmsk::gaussian_cpm_pulse(gmsk::make_gmsk_pulse(k, bt, gmsk::gaussian_span_symbols(bt)),
                                     s.modulation_index)
          : gmsk::rectangular_cpm_pulse(k, s.modulation_index),
      gmsk::CpmArithmetic::kDouble);
}

class GfskTransceiver final : public gmsk::CpmTransceiver<gfsk::GfskFrameReceiver> {
 public:
  explicit GfskTransceiver(const GfskSettings& s)
      : CpmTransceiver("GFSK", s.max_payload_bytes, make_modulator(validated(s)),
                       gfsk::frame_bits(s.preamble_bytes, s.max_payload_bytes), s),
        settings_(s) {}

  std::size_t frame_samples(std::size_t payload_bytes) const override {
    return modulator().frame_samples(gfsk::frame_bits(settings_.preamble_bytes, payload_bytes));
  }

  double sensitivity_snr_db() const override {
    const double at_k8 = settings_.receiver == GfskReceiver::kEnergy ? kSensitivityEnergyDb
                                                                     : kSensitivityDiscriminatorDb;
    return at_k8 - 10.0 * std::log10(settings_.samples_per_symbol / 8.0);
  }

  std::size_t start_frame(const FrameTag& tag, std::span<const std::uint8_t> payload) override {
    check_payload(payload.size());
    return send(gfsk::build_frame_symbols(settings_.preamble_bytes, settings_.whitening, tag,
                                          payload, symbols()));
  }

  // The last CRC symbol's metric window closes within about half a symbol of
  // the frame's last sample (earlier with a Gaussian pulse, whose tail follows
  // it); one symbol covers that and a timing a sample late.
  std::size_t rx_latency_samples() const override { return settings_.samples_per_symbol; }

 private:
  GfskSettings settings_;
};

}  // namespace

std::unique_ptr<Transceiver> make_gfsk_transceiver(const GfskSettings& settings) {
  return std::make_unique<GfskTransceiver>(settings);
}

}  // namespace rfsitl::phy
