#include "dsss_transceiver.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <optional>
#include <stdexcept>
#include <vector>

#include "code_adaptation.hpp"
#include "codes.hpp"
#include "differential_psk.hpp"
#include "frame_format.hpp"
#include "receiver.hpp"
#include "spreader.hpp"

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
  if (s.adapt_windows < 1) throw std::invalid_argument("dsss adapt_windows: must be >= 1");
  if (!(s.adapt_hysteresis_db >= 0.0) || !std::isfinite(s.adapt_hysteresis_db)) {
    throw std::invalid_argument("dsss adapt_hysteresis_db: must be finite and >= 0");
  }
  if (s.adapt_max_candidates < 1 || s.adapt_max_candidates > 1024) {
    throw std::invalid_argument("dsss adapt_max_candidates: " +
                                std::to_string(s.adapt_max_candidates) + " is outside 1..1024");
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
    candidates_ = {0};
    if (s.adaptive) start_adaptation();
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
    if (adaptive_) own_id_ = tag.src;
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
    if (adaptive_) measure(in);
    handler_ = &handler;
    receiver_->push(in, *this);
    handler_ = nullptr;
    if (adaptive_) adapt();
  }

  void reset_receiver() override {
    receiver_->reset();
    if (adaptive_) lag_acc_->break_stream();
  }
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

  std::vector<std::size_t> listen_codes() const override { return listen_; }
  const DsssAdaptationStatus& adaptation_status() const override { return status_; }
  std::size_t candidate_code(std::size_t index) const override { return candidates_.at(index); }
  std::size_t candidate_count() const override { return candidates_.size(); }

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
    if (adaptive_ && f.header_valid) on_adaptive_frame(f);
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

  // ---- cognitive code adaptation (see dsss_transceiver.hpp) ----

  struct Block {
    std::uint64_t start = 0;  // first sample (receiver time)
    std::uint64_t end = 0;    // one past the last
    dsss::LagSums sums;
  };

  void start_adaptation() {
    adaptive_ = true;
    status_.enabled = true;
    const auto list = dsss::adaptation_candidates(book_.front(), settings_.adapt_max_candidates);
    std::vector<std::vector<dsss::Chip>> chips;
    candidates_.clear();
    for (const auto& c : list) {
      candidates_.push_back(c.chips == book_.front().chips ? 0 : add_code(c.name));
      chips.push_back(c.chips);
    }
    selector_ = std::make_unique<dsss::CodeSelector>(std::move(chips));
    const std::size_t length = book_.front().chips.size();
    lag_acc_ =
        std::make_unique<dsss::LagAccumulator>(length, std::max<std::size_t>(1, length / 16));
    total_ = dsss::LagSums(length);
    hold_samples_ = frame_samples(settings_.max_payload_bytes) + period();
    block_samples_ = std::max<std::size_t>(4096, hold_samples_ / 32);
    open_.sums = dsss::LagSums(length);
    last_code_from_.fill(kNoCode);
    set_tx_control(dsss::encode_control({true, 0, 0}));
  }

  // Chip-rate samples (one per chip) into the open block; full blocks to the
  // hold-back queue.
  void measure(std::span<const cf32> in) {
    const unsigned s = settings_.samples_per_chip;
    chips_.clear();
    for (std::size_t i = 0; i < in.size(); ++i) {
      if ((rx_time_ + i) % s == 0) chips_.push_back(in[i]);
    }
    lag_acc_->push(chips_);
    rx_time_ += in.size();
    if (rx_time_ - open_.start >= block_samples_) {
      open_.sums = lag_acc_->take();
      open_.end = rx_time_;
      held_.push_back(std::move(open_));
      open_ = Block{rx_time_, rx_time_, dsss::LagSums(book_.front().chips.size())};
    }
  }

  // A frame of this node's own link ended now: forget what it overlapped.
  void discard_own_frame(std::size_t length_bytes) {
    const std::uint64_t span = frame_samples(length_bytes) + 2 * period();
    const std::uint64_t start = rx_time_ > span ? rx_time_ - span : 0;
    lag_acc_->take();
    open_.start = rx_time_;
    while (!held_.empty() && held_.back().end > start) held_.pop_back();
  }

  void adapt() {
    while (!held_.empty() && held_.front().end + hold_samples_ <= rx_time_) {
      total_.add(held_.front().sums);
      held_.pop_front();
    }
    if (total_.windows < settings_.adapt_windows) return;
    const std::vector<cf32> lags = dsss::normalized_lags(total_);
    total_.clear();
    const auto choice = selector_->choose(lags, preferred_, settings_.adapt_hysteresis_db);
    ++status_.decisions;
    status_.default_sinr_db = selector_->sinr_db(0, lags);
    status_.preferred_sinr_db = choice.sinr_db;
    if (choice.index == preferred_) return;
    if (preferred_ != 0) previous_ = preferred_;
    if (previous_ == choice.index) previous_.reset();
    preferred_ = choice.index;
    epoch_ = static_cast<std::uint8_t>((epoch_ + 1) % (dsss::kMaxControlEpoch + 1));
    ++status_.switches;
    apply_preference();
  }

  void apply_preference() {
    set_tx_control(dsss::encode_control({true, static_cast<std::uint16_t>(preferred_), epoch_}));
    std::vector<std::size_t> listen = {0};
    if (preferred_ != 0) listen.push_back(candidates_[preferred_]);
    if (previous_ && *previous_ != 0) listen.push_back(candidates_[*previous_]);
    set_listen_codes(listen);
    status_.preferred = candidates_[preferred_];
    status_.has_previous = previous_.has_value();
    status_.previous = previous_ ? candidates_[*previous_] : 0;
    status_.epoch = epoch_;
  }

  void on_adaptive_frame(const dsss::ReceivedFrame& f) {
    const NodeId src = f.header.src;
    // Transmitter side: the sender's request says which code to send it on.
    const auto ctrl = dsss::decode_control(f.header.control);
    if (ctrl && ctrl->code_request && ctrl->code_index < candidates_.size() &&
        src != kBroadcastId) {
      const std::uint32_t key = (std::uint32_t{ctrl->code_index} << 4) | ctrl->epoch;
      if (last_request_[src] != key) {
        last_request_[src] = key;
        set_tx_code(src, candidates_[ctrl->code_index]);
      }
    }
    // Receiver side: frames of the own link are not interference.
    if (!own_id_ || f.header.dst != *own_id_) return;
    discard_own_frame(f.header.length);
    if (!f.payload_valid) return;
    last_code_from_[src] = f.code_id;
    if (previous_ && preferred_ != 0 && f.code_id == candidates_[preferred_]) {
      const std::size_t old = candidates_[*previous_];
      const bool someone_on_old = std::any_of(last_code_from_.begin(), last_code_from_.end(),
                                              [&](std::size_t c) { return c == old; });
      if (!someone_on_old) {
        previous_.reset();
        apply_preference();
      }
    }
  }

  static constexpr std::size_t kNoCode = static_cast<std::size_t>(-1);

  bool adaptive_ = false;
  std::vector<std::size_t> candidates_;  // candidate index -> book index
  std::unique_ptr<dsss::CodeSelector> selector_;
  std::unique_ptr<dsss::LagAccumulator> lag_acc_;
  std::vector<cf32> chips_;
  std::uint64_t rx_time_ = 0;
  std::size_t hold_samples_ = 0;
  std::size_t block_samples_ = 0;
  Block open_;
  std::deque<Block> held_;
  dsss::LagSums total_;
  std::size_t preferred_ = 0;  // candidate indices
  std::optional<std::size_t> previous_;
  std::uint8_t epoch_ = 0;
  std::optional<NodeId> own_id_;
  std::array<std::size_t, 256> last_code_from_{};
  std::array<std::uint32_t, 256> last_request_{};
  DsssAdaptationStatus status_;

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
