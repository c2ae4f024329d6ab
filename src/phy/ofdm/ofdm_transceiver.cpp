#include "ofdm_transceiver.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "mac_frame.hpp"
#include "receiver.hpp"
#include "waveform.hpp"

namespace rfsitl::phy {
namespace {

/// Per-sample SNR (dB) at which 80-byte frames reach 10% PER, per rate, as
/// measured by bench/per_vs_snr.sh (500 frames per point); used only to name
/// losses, never to decide them.
double sensitivity_for(unsigned mbps) {
  switch (mbps) {
    case 6:
      return 2.9;
    case 9:
      return 3.7;
    case 12:
      return 5.6;
    case 18:
      return 7.6;
    case 24:
      return 10.2;
    case 36:
      return 13.4;
    case 48:
      return 17.2;
    default:
      return 18.6;
  }
}

class OfdmTransceiver final : public Transceiver {
 public:
  explicit OfdmTransceiver(const OfdmSettings& s) : settings_(s) {
    const auto rate = ofdm::rate_from_mbps(s.rate_mbps);
    if (!rate) {
      throw std::invalid_argument("OFDM rate " + std::to_string(s.rate_mbps) +
                                  " Mbit/s is not one of 6, 9, 12, 18, 24, 36, 48, 54");
    }
    if (s.max_payload_bytes == 0 || s.max_payload_bytes > 4095 - ofdm::kMacOverheadBytes) {
      throw std::invalid_argument("OFDM payload limit must be 1.." +
                                  std::to_string(4095 - ofdm::kMacOverheadBytes) + " octets");
    }
    rate_ = *rate;
    receiver_ = ofdm::make_ofdm_receiver([this](const ofdm::DecodedPpdu& p) { on_ppdu(p); });
  }

  std::size_t max_payload() const override { return settings_.max_payload_bytes; }

  std::size_t frame_samples(std::size_t payload_bytes) const override {
    const auto psdu = static_cast<unsigned>(payload_bytes + ofdm::kMacOverheadBytes);
    return ofdm::kPreambleSamples +
           ofdm::kSymbolSamples * (1 + ofdm::data_symbol_count(rate_, psdu));
  }

  double sensitivity_snr_db() const override { return sensitivity_for(rate_.mbps); }

  bool tx_busy() const override { return tx_pos_ < tx_.size(); }

  std::size_t start_frame(const FrameTag& tag, std::span<const std::uint8_t> payload) override {
    const std::vector<std::uint8_t> psdu = ofdm::encode_mac_frame(tag, payload);
    // Any nonzero seed is valid; vary it per frame as real transmitters do.
    const auto seed = static_cast<std::uint8_t>(1 + tag.serial % 127);
    tx_ = ofdm::build_ppdu(psdu, rate_, seed, false);
    double power = 0.0;
    for (const cf32& s : tx_) power += std::norm(s);
    const auto scale = static_cast<float>(1.0 / std::sqrt(power / static_cast<double>(tx_.size())));
    for (cf32& s : tx_) s *= scale;
    tx_pos_ = 0;
    return tx_.size();
  }

  std::size_t transmit(std::span<cf32> out) override {
    const std::size_t n = std::min(tx_.size() - tx_pos_, out.size());
    std::copy_n(tx_.begin() + static_cast<std::ptrdiff_t>(tx_pos_), n, out.begin());
    std::fill(out.begin() + static_cast<std::ptrdiff_t>(n), out.end(), cf32{});
    tx_pos_ += n;
    return n;
  }

  void receive(std::span<const cf32> in, RxHandler& handler) override {
    handler_ = &handler;
    receiver_->push(in);
    handler_ = nullptr;
  }

  void reset_receiver() override { receiver_->reset(); }

  bool rx_busy() const override { return receiver_->busy(); }

  std::size_t rx_latency_samples() const override { return ofdm::kSymbolSamples; }

 private:
  void on_ppdu(const ofdm::DecodedPpdu& p) {
    if (handler_ == nullptr) return;
    RxEvent ev;
    ev.rssi_db = p.snr_db;
    ev.symbols = p.data_symbols;
    // A bad FCS leaves nothing trustworthy but the fact that a frame was there.
    ev.header_valid = true;
    if (p.fcs_ok) {
      if (const auto mac = ofdm::decode_mac_frame(p.psdu)) {
        ev.tag = mac->tag;
        ev.payload = mac->payload;
        ev.payload_valid = true;
      }
    }
    handler_->on_rx(ev);
  }

  OfdmSettings settings_;
  ofdm::RateParams rate_{};
  std::unique_ptr<ofdm::OfdmReceiver> receiver_;
  std::vector<cf32> tx_;
  std::size_t tx_pos_ = 0;
  RxHandler* handler_ = nullptr;
};

}  // namespace

std::unique_ptr<Transceiver> make_ofdm_transceiver(const OfdmSettings& settings) {
  return std::make_unique<OfdmTransceiver>(settings);
}

}  // namespace rfsitl::phy
