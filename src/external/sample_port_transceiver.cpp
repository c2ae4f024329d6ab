/// Role "samples": B samples each way per tick with a program that owns the
/// node's net port (a GNU Radio flowgraph).
#include <algorithm>
#include <atomic>
#include <optional>
#include <vector>

#include "rfsitl/external/client/tx_report.hpp"
#include "rfsitl/external/external_transceivers.hpp"

namespace rfsitl::external {
namespace {

class SamplePortTransceiver final : public phy::Transceiver {
 public:
  SamplePortTransceiver(std::shared_ptr<NodeLink> link, std::uint32_t tick_samples,
                        std::atomic<std::uint64_t>& overflows)
      : link_(std::move(link)), rx_(tick_samples, cf32{}), overflows_(overflows) {}

  // The program's frames never pass through the emulator's queue or ledger.
  std::size_t max_payload() const override { return 0; }
  std::size_t frame_samples(std::size_t) const override { return 0; }
  double sensitivity_snr_db() const override { return 0.0; }
  std::size_t rx_latency_samples() const override { return 0; }
  bool remote() const override { return true; }

  void begin_tick(std::uint64_t tick, SampleTime time) override {
    tick_ = tick;
    time_ = time;
    if (link_->adopt()) {
      joined_now_ = true;
      reported_overflows_ = 0;  // a new connection's reports count from its welcome
    }
  }

  // transmit() is the tick's round trip, so it runs every tick; and the
  // receiver is opaque, so it always gets its samples.
  bool tx_busy() const override { return true; }
  bool rx_busy() const override { return true; }

  std::size_t start_frame(const phy::FrameTag&, std::span<const std::uint8_t>) override {
    return 0;  // never called: max_payload() == 0 and the emulator serves no net port
  }

  std::size_t transmit(std::span<cf32> out) override {
    std::size_t n = 0;
    if (link_->connected()) {
      MsgHeader h;
      h.type = static_cast<std::uint16_t>(MsgType::kTick);
      h.tick = tick_;
      h.time = static_cast<std::uint64_t>(time_);
      // The first tick after joining has no previous tick to report.
      const std::span<const cf32> rx = joined_now_ ? std::span<const cf32>() : rx_;
      joined_now_ = false;
      const Message* reply = link_->call(h, rx, {}, MsgType::kTx);
      if (reply && reply->samples.size() > out.size()) {
        link_->drop("sent " + std::to_string(reply->samples.size()) + " samples for a tick of " +
                    std::to_string(out.size()));
      } else if (reply && take_report(*reply)) {
        n = reply->samples.size();
        std::copy(reply->samples.begin(), reply->samples.end(), out.begin());
      }
    }
    std::fill(out.begin() + static_cast<std::ptrdiff_t>(n), out.end(), cf32{});
    // Zeros stand for the samples a blanked (transmitting) receiver does not get.
    std::fill(rx_.begin(), rx_.end(), cf32{});
    // What carries signal: up to the last non-zero sample (a burst may end mid-tick).
    while (n > 0 && out[n - 1] == cf32{}) --n;
    return n;
  }

  void receive(std::span<const cf32> in, phy::RxHandler&) override {
    // `in` is the tail of the tick after the node's own transmission.
    std::copy(in.begin(), in.end(), rx_.end() - static_cast<std::ptrdiff_t>(in.size()));
  }

  void reset_receiver() override {}

 private:
  // The process's kTx report (tx_report.hpp), if any, into the node's
  // counters. False after dropping a process whose extra is no report.
  bool take_report(const Message& reply) {
    std::optional<TxReport> report;
    try {
      report = read_tx_report(reply.extra);
    } catch (const TxReportError& e) {
      link_->drop(e.what());
      return false;
    }
    // Totals since the welcome: only the growth is new. (One that shrinks
    // would be the process's mistake; it adds nothing.)
    if (report && report->rx_overflows > reported_overflows_) {
      overflows_.fetch_add(report->rx_overflows - reported_overflows_, std::memory_order_relaxed);
      reported_overflows_ = report->rx_overflows;
    }
    return true;
  }

  std::shared_ptr<NodeLink> link_;
  std::vector<cf32> rx_;  // this tick's received samples, sent with the next tick
  std::uint64_t tick_ = 0;
  SampleTime time_ = 0;
  bool joined_now_ = false;
  std::atomic<std::uint64_t>& overflows_;  // the node's NodeCounters::external_overflows
  std::uint64_t reported_overflows_ = 0;   // the connection's latest total
};

/// Another rank's samples node: the figures of SamplePortTransceiver, and no
/// work (this rank never runs the node's TX or RX).
class SamplePortStandIn final : public phy::Transceiver {
 public:
  std::size_t max_payload() const override { return 0; }
  std::size_t frame_samples(std::size_t) const override { return 0; }
  double sensitivity_snr_db() const override { return 0.0; }
  std::size_t rx_latency_samples() const override { return 0; }
  bool tx_busy() const override { return true; }
  bool rx_busy() const override { return true; }
  std::size_t start_frame(const phy::FrameTag&, std::span<const std::uint8_t>) override {
    return 0;
  }
  std::size_t transmit(std::span<cf32> out) override {
    std::fill(out.begin(), out.end(), cf32{});
    return 0;
  }
  void receive(std::span<const cf32>, phy::RxHandler&) override {}
  void reset_receiver() override {}
};

}  // namespace

std::unique_ptr<phy::Transceiver> make_sample_port_stand_in() {
  return std::make_unique<SamplePortStandIn>();
}

std::unique_ptr<phy::Transceiver> make_sample_port_transceiver(
    std::shared_ptr<NodeLink> link, std::uint32_t tick_samples,
    std::atomic<std::uint64_t>& overflows) {
  return std::make_unique<SamplePortTransceiver>(std::move(link), tick_samples, overflows);
}

}  // namespace rfsitl::external
