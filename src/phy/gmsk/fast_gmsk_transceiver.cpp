#include "rfsitl/phy/gmsk/fast_gmsk_transceiver.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "frame_receiver.hpp"
#include "rfsitl/phy/gmsk/cpm_modulator.hpp"
#include "rfsitl/phy/gmsk/frame_format.hpp"
#include "rfsitl/phy/gmsk/gmsk_pulse.hpp"

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

class FastGmskTransceiver final : public Transceiver {
 public:
  explicit FastGmskTransceiver(const FastGmskSettings& s)
      : settings_(validated(s)),
        pulse_(
            gmsk::make_gmsk_pulse(s.samples_per_symbol, s.bandwidth_time, s.filter_span_symbols)),
        modulator_(pulse_),
        symbols_(gmsk::frame_symbol_count(s.max_payload_bytes)),
        receiver_(pulse_, s.max_payload_bytes) {}

  std::size_t max_payload() const override { return settings_.max_payload_bytes; }

  std::size_t frame_samples(std::size_t payload_bytes) const override {
    return modulator_.frame_samples(gmsk::frame_symbol_count(payload_bytes));
  }

  double sensitivity_snr_db() const override {
    return kSensitivityK2Db - 10.0 * std::log10(settings_.samples_per_symbol / 2.0);
  }

  bool tx_busy() const override { return modulator_.samples_left() > 0; }

  std::size_t start_frame(const FrameTag& tag, std::span<const std::uint8_t> payload) override {
    // A precondition, but a cheap one to check, and the frame buffer is sized by it.
    if (payload.size() > settings_.max_payload_bytes) {
      throw std::invalid_argument("fast GMSK payload of " + std::to_string(payload.size()) +
                                  " bytes exceeds max_payload_bytes " +
                                  std::to_string(settings_.max_payload_bytes));
    }
    const std::size_t n = gmsk::build_frame_symbols(tag, payload, symbols_);
    return modulator_.start(std::span(symbols_).first(n));
  }

  std::size_t transmit(std::span<cf32> out) override {
    const std::size_t n = modulator_.generate(out);
    std::fill(out.begin() + static_cast<std::ptrdiff_t>(n), out.end(), cf32{});
    return n;
  }

  void receive(std::span<const cf32> in, RxHandler& handler) override {
    receiver_.push(in, handler);
  }

  void reset_receiver() override { receiver_.reset(); }

  bool rx_busy() const override { return receiver_.busy(); }

  // The decode comes k samples before the frame's end: the last CRC symbol's
  // matched-filter window closes then (the tail symbols follow it). Decodes
  // thus land within one symbol of the end; two allow for a timing a sample off.
  std::size_t rx_latency_samples() const override { return 2 * settings_.samples_per_symbol; }

 private:
  FastGmskSettings settings_;
  gmsk::GmskPulse pulse_;
  gmsk::CpmModulator modulator_;
  std::vector<std::int8_t> symbols_;
  gmsk::FrameReceiver receiver_;
};

}  // namespace

std::unique_ptr<Transceiver> make_fast_gmsk_transceiver(const FastGmskSettings& settings) {
  return std::make_unique<FastGmskTransceiver>(settings);
}

}  // namespace rfsitl::phy
