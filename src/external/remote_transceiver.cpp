/// Role "transceiver": the engine's calls, forwarded to an `rfsitl node` process.
#include <algorithm>
#include <cstring>
#include <optional>
#include <vector>

#include "rfsitl/external/external_transceivers.hpp"
#include "rfsitl/registry/phy_registry.hpp"

namespace rfsitl::external {
namespace {

class RemoteTransceiver final : public phy::Transceiver {
 public:
  RemoteTransceiver(std::shared_ptr<NodeLink> link, const scenario::PhyChoice& phy)
      : link_(std::move(link)), shadow_(phy::make_transceiver(phy.type, phy.settings)) {}

  std::size_t max_payload() const override { return shadow_->max_payload(); }
  std::size_t frame_samples(std::size_t bytes) const override {
    return shadow_->frame_samples(bytes);
  }
  double sensitivity_snr_db() const override { return shadow_->sensitivity_snr_db(); }
  std::size_t rx_latency_samples() const override { return shadow_->rx_latency_samples(); }
  bool remote() const override { return true; }

  void begin_tick(std::uint64_t tick, SampleTime time) override {
    tick_ = tick;
    time_ = time;
    if (link_->adopt()) {
      // A new process starts with an idle PHY; mirror that.
      tx_busy_ = false;
      rx_busy_ = false;
      reset_pending_ = false;
      start_.clear();
    }
    // An idle node makes no round trip that would notice its process die, and
    // a drop must be counted (and the TX queue held) when it happens, not at
    // the next frame. The samples role needs no such check: it makes a round
    // trip every tick.
    link_->watch_peer();
  }

  // While the process is away the TX queue holds: nothing is started into the void.
  bool tx_busy() const override { return !link_->connected() || tx_busy_; }
  bool rx_busy() const override { return link_->connected() && rx_busy_; }

  std::size_t start_frame(const phy::FrameTag& tag,
                          std::span<const std::uint8_t> payload) override {
    const FrameStart head{tag.serial, tag.src, tag.dst, 0};
    start_.resize(sizeof head + payload.size());
    std::memcpy(start_.data(), &head, sizeof head);
    std::copy(payload.begin(), payload.end(), start_.begin() + sizeof head);
    tx_busy_ = true;
    return shadow_->frame_samples(payload.size());
  }

  std::size_t transmit(std::span<cf32> out) override {
    std::size_t n = 0;
    if (link_->connected()) {
      MsgHeader h = header(MsgType::kTxRequest);
      h.flags = start_.empty() ? 0 : kFlagStartFrame;
      const Message* reply = link_->call(h, {}, start_, MsgType::kTx);
      start_.clear();
      if (reply && reply->samples.size() > out.size()) {
        link_->drop("sent " + std::to_string(reply->samples.size()) + " samples for a tick of " +
                    std::to_string(out.size()));
      } else if (reply) {
        n = reply->samples.size();
        std::copy(reply->samples.begin(), reply->samples.end(), out.begin());
        tx_busy_ = (reply->header.flags & kFlagTxBusy) != 0;
      }
    }
    std::fill(out.begin() + static_cast<std::ptrdiff_t>(n), out.end(), cf32{});
    return n;
  }

  void receive(std::span<const cf32> in, phy::RxHandler& handler) override {
    if (!link_->connected()) return;
    MsgHeader h = header(MsgType::kRx);
    h.flags = reset_pending_ ? kFlagResetReceiver : 0;
    reset_pending_ = false;
    const Message* reply = link_->call(h, in, {}, MsgType::kRxResult);
    if (!reply) return;
    rx_busy_ = (reply->header.flags & kFlagRxBusy) != 0;
    report_decodes(reply->extra, handler);
  }

  void reset_receiver() override {
    reset_pending_ = true;
    rx_busy_ = false;  // as the PHY itself reports right after a reset
  }

 private:
  MsgHeader header(MsgType type) const {
    MsgHeader h;
    h.type = static_cast<std::uint16_t>(type);
    h.tick = tick_;
    h.time = static_cast<std::uint64_t>(time_);
    return h;
  }

  void report_decodes(const std::vector<std::uint8_t>& extra, phy::RxHandler& handler) {
    std::size_t at = 0;
    while (at < extra.size()) {
      DecodeRecord r;
      if (extra.size() - at < sizeof r) return link_->drop("truncated decode record");
      std::memcpy(&r, extra.data() + at, sizeof r);
      at += sizeof r;
      const std::size_t symbol_bytes = std::size_t{r.symbol_count} * sizeof(cf32);
      if (extra.size() - at < r.payload_bytes + symbol_bytes) {
        return link_->drop("truncated decode payload");
      }
      symbols_.resize(r.symbol_count);
      if (symbol_bytes > 0) {
        std::memcpy(symbols_.data(), extra.data() + at + r.payload_bytes, symbol_bytes);
      }
      phy::RxEvent ev;
      ev.tag = phy::FrameTag{r.src, r.dst, r.serial};
      ev.payload = std::span(extra.data() + at, r.payload_bytes);
      ev.header_valid = r.header_valid != 0;
      ev.payload_valid = r.payload_valid != 0;
      ev.rssi_db = r.rssi_db;
      ev.evm_db = r.evm_db;
      ev.symbols = symbols_;
      at += r.payload_bytes + symbol_bytes;
      handler.on_rx(ev);
    }
  }

  std::shared_ptr<NodeLink> link_;
  std::unique_ptr<phy::Transceiver> shadow_;  // lengths and sensitivity only
  std::uint64_t tick_ = 0;
  SampleTime time_ = 0;
  bool tx_busy_ = false;
  bool rx_busy_ = false;
  bool reset_pending_ = false;
  std::vector<std::uint8_t> start_;  // FrameStart + payload, sent with the next kTxRequest
  std::vector<cf32> symbols_;        // the decode being reported (aligned copy)
};

}  // namespace

std::unique_ptr<phy::Transceiver> make_remote_transceiver(std::shared_ptr<NodeLink> link,
                                                          const scenario::PhyChoice& phy) {
  return std::make_unique<RemoteTransceiver>(std::move(link), phy);
}

}  // namespace rfsitl::external
