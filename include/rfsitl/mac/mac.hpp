#pragma once
/// The medium access layer of one node, between its TX queue and its
/// transceiver: when a frame may start, which frames the MAC sends of its own
/// (ACKs), and what it makes of the frames its receiver decodes.
///
/// Time. The engine runs in ticks of B samples, and a MAC acts once per tick:
/// a transmission it asks for starts at the tick's first sample, and carrier
/// sense reports a whole tick after it was received. Every MAC time (slot,
/// SIFS, DIFS, a TDMA slot) is therefore a whole number of ticks, rounded up
/// from its setting; the banner and the summary print the times really used,
/// and every comparison (Bianchi's model) uses them. All of it runs on the
/// sample clock, so a virtual-time run is deterministic.
///
/// Threads: the engine calls a node's MAC on its own thread only, serially.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "rfsitl/common/net_frame.hpp"
#include "rfsitl/common/types.hpp"
#include "rfsitl/config/component_info.hpp"
#include "rfsitl/mac/mac_counters.hpp"

namespace rfsitl::mac {

/// What a MAC knows of its node and of the engine, fixed for the run.
struct MacContext {
  NodeId id = 0;
  std::size_t index = 0;  ///< the node's place in the scenario's list (TDMA slot order)
  std::size_t num_nodes = 1;
  double sample_rate_hz = 1e6;
  std::size_t tick_samples = 250;  ///< B: MAC times are whole ticks of B samples
  /// Bytes one radio frame carries, the kind byte and the MAC header included.
  std::size_t radio_max_payload = 0;
  /// Air time, in samples, of a radio frame carrying `bytes` (kind byte and MAC
  /// header included): the transceiver's frame_samples().
  std::function<std::size_t(std::size_t bytes)> frame_samples;
  /// The longest a receiver takes, after a frame's last sample, to report it
  /// (the worst of every node's transceiver, plus the channel's longest delay).
  std::size_t rx_latency_samples = 0;
  std::uint64_t seed = 1;           ///< this node's random stream (backoff draws)
  MacCounters* counters = nullptr;  ///< where the MAC counts (outlives the MAC)
};

/// The frames waiting for the MAC: its node's TX queue.
class FrameQueue {
 public:
  virtual ~FrameQueue() = default;
  /// The frame that may start at this tick, or nullptr.
  virtual const NetFrame* peek() = 0;
  /// Takes that frame. Precondition: peek() != nullptr.
  virtual NetFrame take() = 0;
};

/// A transmission the MAC asks for: it starts at the current tick's first sample.
struct MacTransmission {
  FrameKind kind = FrameKind::kAgent;  ///< kMacControl for the MAC's own frames
  NodeId dst = 0;
  /// A handed-in frame (kind != kMacControl): owned by the MAC, valid until its
  /// next call. nullptr for a control frame.
  const NetFrame* frame = nullptr;
  /// The MAC header before a data frame's payload, or a control frame's whole
  /// content; on the air after the kind byte. Valid until the MAC's next call.
  std::span<const std::uint8_t> header;
  bool retry = false;  ///< a repeat of the frame sent last (after an ACK timeout)
  /// The frame's outcome waits for the MAC's verdict (an ACK, or giving up):
  /// the ledger then counts the frame once, however many attempts it takes.
  bool awaits_verdict = false;
};

/// How a frame that awaited its verdict ended at the sender.
enum class Verdict : std::uint8_t {
  kAcknowledged,  ///< its ACK came
  kGaveUp,        ///< no ACK after the retry limit's attempts
};

/// What the MAC decides about a data frame its receiver decoded.
struct RxDecision {
  bool deliver = true;  ///< false: a repeat of a frame already delivered
};

class Mac {
 public:
  virtual ~Mac() = default;

  /// Bytes of MAC header before every data frame's payload (0 for none).
  virtual std::size_t header_bytes() const = 0;

  /// Largest radio frame (kind byte and header included) this MAC sends, at
  /// most MacContext::radio_max_payload; a TDMA slot may hold less.
  virtual std::size_t max_radio_payload() const = 0;

  /// Whether the MAC listens before talking, and how: nullopt when it does not;
  /// otherwise the energy threshold, in dB over the noise power, at which the
  /// engine reports a tick as busy to on_sensed().
  virtual std::optional<double> carrier_sense_db() const = 0;

  /// Once per tick, before the transceivers run. `now`: the tick's first
  /// sample; `tx_busy`: the node's transmitter is still sending. Returns the
  /// transmission to start now (only when !tx_busy), or nothing.
  virtual std::optional<MacTransmission> on_tick(SampleTime now, bool tx_busy,
                                                 FrameQueue& queue) = 0;

  // The calls below have no-op defaults: a MAC that neither listens nor
  // acknowledges (none, tdma) overrides none of them.

  /// The transmission on_tick() asked for is on the air during [start, end).
  virtual void on_sent(SampleTime /*start*/, SampleTime /*end*/) {}

  /// A frame that awaited its verdict got it during the last call (on_tick()
  /// for a give-up, on_control() for an ACK); cleared by reading.
  virtual std::optional<Verdict> take_verdict() { return std::nullopt; }

  /// Carrier sense over the tick just received, once per tick after the
  /// receivers ran: `busy` when the node transmitted in it, or its receiver was
  /// inside a frame it detected, or heard energy over the MAC's threshold.
  /// Only called when carrier_sense_db() has a value.
  virtual void on_sensed(bool /*busy*/) {}

  /// The receiver decoded a data frame from `src` with this MAC `header`,
  /// unicast to this node (`to_me`) or broadcast. `now`: the current tick.
  virtual RxDecision on_data(NodeId /*src*/, std::span<const std::uint8_t> /*header*/,
                             bool /*to_me*/, SampleTime /*now*/) {
    return {};
  }

  /// The receiver decoded a MAC control frame from `src` addressed to this node.
  virtual void on_control(NodeId /*src*/, std::span<const std::uint8_t> /*content*/,
                          SampleTime /*now*/) {}

  /// One line for the banner: the MAC and its times as really used.
  virtual std::string describe() const = 0;
};

/// A MAC as the registry lists it: its declarations and its factory.
struct MacComponent {
  config::ComponentInfo info;  ///< kind "mac"
  /// Builds one node's MAC from settings that passed info.validate(). Throws
  /// std::invalid_argument when the settings cannot work with this PHY (a
  /// TDMA slot too short for any frame).
  std::function<std::unique_ptr<Mac>(const config::Settings&, const MacContext&)> make;
};

}  // namespace rfsitl::mac
