#include "fast_gmsk_transceiver.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "cpm_modulator.hpp"
#include "cpm_transceiver.hpp"
#include "frame_format.hpp"
#include "frame_receiver.hpp"
#include "gmsk_pulse.hpp"

namespace rfsitl::phy {
namespace {

/// Per-sample SNR (dB) at which 80-byte frames reach 10% PER at k = 2,
/// BT = 0.5, L = 3 (2000 frames per point; bench/fast_gmsk_bench.cpp).
constexpr double kSensitivityK2Db = 5.3;

const FastGmskSettings& validated(const FastGmskSettings& s) {
  if (s.samples_per_symbol < 2 || s.samples_per_symbol > 8) {
    throw std::invalid_argument("FastGmskSettings.samples_per_symbol must be 2..8, got " +
                                std::to_string(s.samples_per_symbol));
  }
  if (!(s.bandwidth_time >= 0.2F && s.bandwidth_time <= 1.0F)) {
    throw std::invalid_argument("FastGmskSettings.bandwidth_time must be in [0.2, 1], got " +
                                std::to_string(s.bandwidth_time));
  }
  if (s.filter_span_symbols < 1 || s.filter_span_symbols > 8) {
    throw std::invalid_argument("FastGmskSettings.filter_span_symbols must be 1..8, got " +
                                std::to_string(s.filter_span_symbols));
  }
  if (s.max_payload_bytes < 1 || s.max_payload_bytes > gmsk::kMaxPayloadBytes) {
    throw std::invalid_argument("FastGmskSettings.max_payload_bytes must be 1..65535, got " +
                                std::to_string(s.max_payload_bytes));
  }
  return s;
}

/// Precondition: `s` validated (the pulse's tables are sized by it).
gmsk::GmskPulse pulse_of(const FastGmskSettings& s) {
  return gmsk::make_gmsk_pulse(s.samples_per_symbol, s.bandwidth_time, s.filter_span_symbols);
}

class FastGmskTransceiver final : public gmsk::CpmTransceiver<gmsk::FrameReceiver> {
 public:
  explicit FastGmskTransceiver(const FastGmskSettings& s)
      : FastGmskTransceiver(s, pulse_of(validated(s))) {}

  std::size_t frame_samples(std::size_t payload_bytes) const override {
    return modulator().frame_samples(gmsk::frame_symbol_count(payload_bytes));
  }

  double sensitivity_snr_db() const override {
    return kSensitivityK2Db - 10.0 * std::log10(settings_.samples_per_symbol / 2.0);
  }

  std::size_t start_frame(const FrameTag& tag, std::span<const std::uint8_t> payload) override {
    check_payload(payload.size());
    return send(gmsk::build_frame_symbols(tag, payload, symbols()));
  }

  // The decode comes k samples before the frame's end: the last CRC symbol's
  // matched-filter window closes then (the tail symbols follow it). Decodes
  // thus land within one symbol of the end; two allow for a timing a sample off.
  std::size_t rx_latency_samples() const override { return 2 * settings_.samples_per_symbol; }

 private:
  // h = 1/2: the finished symbols as exact quarter turns, the rest in float.
  FastGmskTransceiver(const FastGmskSettings& s, const gmsk::GmskPulse& pulse)
      : CpmTransceiver("fast GMSK", s.max_payload_bytes,
                       gmsk::CpmModulator(gmsk::gaussian_cpm_pulse(pulse, 0.5),
                                          gmsk::CpmArithmetic::kFloatQuarterTurns),
                       gmsk::frame_symbol_count(s.max_payload_bytes), pulse, s.max_payload_bytes),
        settings_(s) {}

  FastGmskSettings settings_;
};

}  // namespace

std::unique_ptr<Transceiver> make_fast_gmsk_transceiver(const FastGmskSettings& settings) {
  return std::make_unique<FastGmskTransceiver>(settings);
}

}  // namespace rfsitl::phy
