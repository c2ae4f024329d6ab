#pragma once
// One node as the lock-step engine holds it (lock_step_engine.hpp): its transceiver,
// MAC and TX queue, and what the current tick's phases leave for the next.
// Internal to the engine module.
#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <utility>
#include <vector>

#include "event_reporter.hpp"
#include "rfsitl/channel/channel.hpp"
#include "rfsitl/common/spsc_ring.hpp"
#include "rfsitl/engine/engine.hpp"
#include "rfsitl/mac/mac.hpp"
#include "rfsitl/phy/transceiver.hpp"

namespace rfsitl::engine {

/// A frame waiting in a node's TX queue. It may start at the first tick that
/// begins at or after `not_before`, the virtual time at which it arrived.
struct QueuedFrame {
  NetFrame frame;
  SampleTime not_before = 0;
};

/// One decode reported by a receiver during the RX phase, handled afterwards.
struct Decoded {
  phy::FrameTag tag;
  std::vector<std::uint8_t> payload;
  bool payload_valid;
};

/// A MAC's verdict on a frame that awaited one, for the ledger (serially).
struct PendingVerdict {
  std::uint32_t frame;  // the serial of the frame's first attempt
  mac::Verdict verdict;
};

struct Node : phy::RxHandler, mac::FrameQueue {
  NodeId id = 0;
  std::unique_ptr<phy::Transceiver> radio;
  std::unique_ptr<mac::Mac> mac;
  std::unique_ptr<SpscRing<QueuedFrame>> queue;  // from the agent ports (submit())
  std::unique_ptr<std::mutex> producers;         // taken by submit(): one producer at a time
  std::vector<std::uint8_t> typed_payload;       // the frame on the air with kind and MAC header
  std::deque<NetFrame> injected;                 // scenario traffic, engine thread only
  SampleTime queue_now = 0;                      // the tick the MAC takes frames at
  // Carrier sense (MACs that listen): the energy threshold (absolute power),
  // and what this tick's RX phase found.
  std::optional<float> busy_power;
  bool sensed_busy = false;
  bool hears_others = false;  // another transmitter's signal reaches it this tick
  // The MAC's frame that awaits a verdict (the serial of its first attempt),
  // and a verdict reached during the TX phase, for the ledger.
  std::uint32_t mac_frame = 0;
  std::optional<PendingVerdict> verdict;
  bool started_awaits_verdict = false;  // the frame started this tick awaits one
  bool started_first_attempt = true;    // ... and is not a repeat
  std::vector<cf32> tx;                 // this tick's TX samples
  std::vector<cf32> rx;                 // this tick's RX samples
  bool active = false;                  // tx carries signal this tick
  std::size_t tx_samples = 0;           // leading samples of tx that carry signal
  bool receiver_blanked = false;        // T/R switch on transmit since last tick
  bool full_duplex = false;             // no T/R switch: receives while it transmits (FDD)
  std::uint32_t frames_started = 0;
  // Set by the TX phase when a frame starts this tick; consumed serially.
  std::optional<std::pair<std::uint32_t, NetFrame>> started;
  std::size_t started_len = 0;
  SampleTime frame_end = 0;           // end of the latest frame this node started
  channel::Channel::Scratch scratch;  // this receiver's, for the channel's receive()
  std::vector<Decoded> decoded;
  /// kWatched: the receiver is idle (skipped) but an observer wants its input,
  /// so the input is computed and the receiver is not run: watching changes no
  /// receiver's state, hence no outcome.
  /// kElsewhere: another rank of a distributed run owns the node.
  enum class RxTick { kRan, kSkipped, kBlanked, kWatched, kElsewhere } rx_tick = RxTick::kRan;
  bool watched = false;  // an observer wants this tick's samples
  std::size_t index = 0;
  SampleTime tick_time = 0;
  const EventReporter* reporter = nullptr;

  void on_rx(const phy::RxEvent& ev) override {
    if (!ev.header_valid) return;
    decoded.push_back(Decoded{ev.tag, {ev.payload.begin(), ev.payload.end()}, ev.payload_valid});
    if (reporter->active()) reporter->decoded(index, tick_time, ev);
  }

  // mac::FrameQueue: the scenario's traffic first, then the TX queue's head
  // once it has arrived.
  const NetFrame* peek() override {
    if (!injected.empty()) return &injected.front();
    const QueuedFrame* head = queue->peek();
    return head != nullptr && head->not_before <= queue_now ? &head->frame : nullptr;
  }
  NetFrame take() override {
    if (!injected.empty()) {
      NetFrame f = std::move(injected.front());
      injected.pop_front();
      return f;
    }
    return std::move(queue->try_pop()->frame);
  }
};

}  // namespace rfsitl::engine
