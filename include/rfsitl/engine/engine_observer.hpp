#pragma once
/// What the engine shows to traces, recordings and the dashboard. Observers
/// are called synchronously; each call must be quick (copy and hand off).
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "rfsitl/common/types.hpp"
#include "rfsitl/engine/frame_event.hpp"
#include "rfsitl/phy/transceiver.hpp"

namespace rfsitl::engine {

class EngineObserver {
 public:
  virtual ~EngineObserver() = default;

  /// Every frame event. kHandedIn and kQueueDropped of agents' frames come from
  /// the I/O thread, all others from the engine thread: implementations must be
  /// thread-safe. Events of one frame arrive in order.
  virtual void on_frame_event(const FrameEvent& event) = 0;

  /// Engine thread, in every tick for which wants_samples() was true:
  /// the samples its receiver got in the tick starting at `time` (B of them;
  /// zeros where its own transmission blanked it; the receiver's front-end
  /// scale, noise at unit power).
  virtual void on_rx_samples(std::size_t /*node*/, SampleTime /*time*/,
                             std::span<const cf32> /*samples*/) {}

  /// Engine thread: whether node `node`'s received samples of the tick
  /// [tick_start, tick_start + tick_samples) are wanted. Asked once per tick
  /// and node; cheap. Wanting samples costs their computation (mixing and
  /// noise) in ticks the engine would otherwise skip, so want only the ticks you
  /// need; it never runs a receiver that would not have run, so it changes no
  /// outcome.
  virtual bool wants_samples(std::size_t /*node*/, SampleTime /*tick_start*/,
                             std::size_t /*tick_samples*/) const {
    return false;
  }

  /// Engine thread: the radio of the node with id `node` transmits on tx_hz
  /// and receives on rx_hz from the tick starting at `time` on (Engine::retune).
  virtual void on_retune(NodeId /*node*/, SampleTime /*time*/, double /*tx_hz*/, double /*rx_hz*/) {
  }

  /// Worker thread of node `node` (several may call at once): a decode with a
  /// valid header in the tick starting at `time`; `event.symbols` is the
  /// constellation (valid during the call only).
  virtual void on_decode(std::size_t /*node*/, SampleTime /*time*/, const phy::RxEvent& /*event*/) {
  }

  /// Distributed runs: an observer that shows every rank's nodes (the
  /// dashboard's live view, on rank 0) sees only its own rank's events and
  /// samples; observers with the same non-empty share_key() on every rank
  /// swap what they saw. Engine thread, with the node counters (every 0.1 s
  /// of virtual time and at the end): share() is this rank's part, and
  /// take_share() gets each other rank's (`rank`), which replaces what that
  /// rank shared before. The bytes are the observer's own format; a reader
  /// must check them (a short or inconsistent share is dropped, not trusted).
  virtual std::string_view share_key() const { return {}; }
  virtual std::vector<std::uint8_t> share() { return {}; }
  virtual void take_share(std::size_t /*rank*/, std::span<const std::uint8_t> /*bytes*/) {}
};

}  // namespace rfsitl::engine
