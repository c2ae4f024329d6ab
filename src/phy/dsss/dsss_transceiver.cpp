#include "rfsitl/phy/dsss/dsss_transceiver.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <vector>

#include "rfsitl/phy/dsss/codes.hpp"
#include "rfsitl/phy/dsss/differential_psk.hpp"
#include "rfsitl/phy/dsss/frame_format.hpp"
#include "rfsitl/phy/dsss/receiver.hpp"
#include "rfsitl/phy/dsss/spreader.hpp"

namespace rfsitl::phy {
namespace {

using dsss::Modulation;

dsss::SpreadingCode parse_code(const std::string& name) {
  try {
    return dsss::code_by_name(name);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("dsss code: ") + e.what());
  }
}

Modulation parse_modulation(const std::string& name) {
  const auto m = dsss::modulation_from_name(name);
  if (!m) {
    throw std::invalid_argument("dsss modulation: '" + name + "' is not dbpsk or dqpsk");
  }
  return *m;
}

void check_numbers(const DsssSettings& s) {
  if (s.samples_per_chip < 1 || s.samples_per_chip > 8) {
    throw std::invalid_argument("dsss samples_per_chip: " + std::to_string(s.samples_per_chip) +
                                " is outside 1..8");
  }
  if (s.max_payload_bytes < 1 || s.max_payload_bytes > dsss::kMaxPayloadBytes) {
    throw std::invalid_argument("dsss max_payload_bytes: " + std::to_string(s.max_payload_bytes) +
                                " is outside 1.." + std::to_string(dsss::kMaxPayloadBytes));
  }
}

class DsssTransceiverImpl final : public DsssTransceiver, private dsss::FrameSink {
 public:
  explicit DsssTransceiverImpl(const DsssSettings& s)
      : settings_(s), modulation_(parse_modulation(s.modulation)) {
    book_.push_back(parse_code(s.code));
    check_numbers(s);
    listen_ = {0};
    receiver_ = std::make_unique<dsss::DsssReceiver>(
        dsss::ReceiverSettings{s.samples_per_chip, s.max_payload_bytes}, listen_codes(listen_));
  }

  std::size_t max_payload() const override { return settings_.max_payload_bytes; }

  std::size_t frame_samples(std::size_t payload_bytes) const override {
    return dsss::frame_symbol_count(modulation_, payload_bytes) * period();
  }

  // Measured with bench/dsss_per_bench.cpp (80-byte frames, PER 10%): from
  // Barker-11 to gold1023 DBPSK needs 9.2 +- 0.3 dB of SNR after despreading,
  // so the per-sample figure falls by the processing gain 10 log10(L S);
  // DQPSK needs 4.4 dB more. Only used to name losses.
  double sensitivity_snr_db() const override {
    const double gain = 10.0 * std::log10(static_cast<double>(period()));
    return kDbpskDespreadSnrDb - gain + (modulation_ == Modulation::kDqpsk ? kDqpskExtraDb : 0.0);
  }

  bool tx_busy() const override { return spreader_.remaining() > 0; }

  std::size_t start_frame(const FrameTag& tag, std::span<const std::uint8_t> payload) override {
    dsss::FrameHeader h;
    h.modulation = modulation_;
    h.length = static_cast<std::uint16_t>(payload.size());
    h.src = tag.src;
    h.dst = tag.dst;
    h.serial = tag.serial;
    h.control = tx_control_;
    spreader_.start(book_[tx_code(tag.dst)].chips, settings_.samples_per_chip,
                    dsss::frame_symbols(h, payload));
    return spreader_.remaining();
  }

  std::size_t transmit(std::span<cf32> out) override {
    const std::size_t n = spreader_.write(out);
    std::fill(out.begin() + static_cast<std::ptrdiff_t>(n), out.end(), cf32{});
    return n;
  }

  void receive(std::span<const cf32> in, RxHandler& handler) override {
    handler_ = &handler;
    receiver_->push(in, *this);
    handler_ = nullptr;
  }

  void reset_receiver() override { receiver_->reset(); }
  bool rx_busy() const override { return receiver_->busy(); }
  // The last symbol is despread at the frame's last sample; with S >= 2 the
  // early-late gate also reads the sample after it.
  std::size_t rx_latency_samples() const override { return settings_.samples_per_chip > 1 ? 1 : 0; }

  std::size_t add_code(const std::string& name) override {
    dsss::SpreadingCode code = parse_code(name);
    for (std::size_t i = 0; i < book_.size(); ++i) {
      if (book_[i].name == code.name) return i;
    }
    if (code.chips.size() != book_.front().chips.size()) {
      throw std::invalid_argument("dsss code: '" + code.name + "' has " +
                                  std::to_string(code.chips.size()) + " chips, the default '" +
                                  book_.front().name + "' " +
                                  std::to_string(book_.front().chips.size()));
    }
    book_.push_back(std::move(code));
    return book_.size() - 1;
  }

  std::size_t code_count() const override { return book_.size(); }

  const std::string& code_name(std::size_t index) const override { return book_.at(index).name; }

  void set_tx_code(NodeId dst, std::size_t code) override {
    check_index(code);
    tx_table_[dst] = code;
  }

  std::size_t tx_code(NodeId dst) const override { return tx_table_[dst].value_or(0); }

  void set_listen_codes(std::span<const std::size_t> codes) override {
    if (codes.empty() || codes.size() > dsss::kMaxListenCodes) {
      throw std::invalid_argument("dsss: listen on 1.." + std::to_string(dsss::kMaxListenCodes) +
                                  " codes, not " + std::to_string(codes.size()));
    }
    for (const std::size_t c : codes) check_index(c);
    listen_.assign(codes.begin(), codes.end());
    receiver_->set_codes(listen_codes(listen_));
  }

  void set_tx_control(std::uint16_t control) override { tx_control_ = control; }

  const DsssRxInfo& last_rx_info() const override { return info_; }

 private:
  // Despread SNR at which 80-byte frames see 10% PER (see above).
  static constexpr double kDbpskDespreadSnrDb = 9.2;
  static constexpr double kDqpskExtraDb = 4.4;

  std::size_t period() const { return book_.front().chips.size() * settings_.samples_per_chip; }

  void check_index(std::size_t code) const {
    if (code >= book_.size()) {
      throw std::out_of_range("dsss: code book index " + std::to_string(code) + " is not below " +
                              std::to_string(book_.size()));
    }
  }

  std::vector<dsss::ListenCode> listen_codes(const std::vector<std::size_t>& indices) const {
    std::vector<dsss::ListenCode> out;
    for (const std::size_t i : indices) out.push_back({i, book_[i].chips});
    return out;
  }

  void on_frame(const dsss::ReceivedFrame& f) override {
    info_ = DsssRxInfo{f.code_id, f.header_valid ? f.header.control : std::uint16_t{0},
                       f.despread_snr_db};
    if (handler_ == nullptr) return;
    RxEvent ev;
    ev.header_valid = f.header_valid;
    ev.payload_valid = f.payload_valid;
    if (f.header_valid) ev.tag = FrameTag{f.header.src, f.header.dst, f.header.serial};
    ev.payload = f.payload;
    ev.rssi_db = f.rssi_db;
    ev.evm_db = -f.despread_snr_db;
    ev.symbols = f.symbols;
    handler_->on_rx(ev);
  }

  DsssSettings settings_;
  Modulation modulation_;
  std::vector<dsss::SpreadingCode> book_;
  std::array<std::optional<std::size_t>, 256> tx_table_{};
  std::vector<std::size_t> listen_;
  std::uint16_t tx_control_ = 0;
  dsss::Spreader spreader_;
  std::unique_ptr<dsss::DsssReceiver> receiver_;
  RxHandler* handler_ = nullptr;
  DsssRxInfo info_;
};

}  // namespace

std::unique_ptr<DsssTransceiver> make_code_agile_dsss_transceiver(const DsssSettings& settings) {
  return std::make_unique<DsssTransceiverImpl>(settings);
}

std::unique_ptr<Transceiver> make_dsss_transceiver(const DsssSettings& settings) {
  return make_code_agile_dsss_transceiver(settings);
}

}  // namespace rfsitl::phy
