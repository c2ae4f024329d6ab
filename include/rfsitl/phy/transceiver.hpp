#pragma once
/// The virtual software-defined radio of one node: a TX path that turns frames
/// into complex baseband samples and an RX path that turns received samples
/// back into frames. The engine drives it in lock-step ticks.
#include <cstdint>
#include <span>
#include <string>

#include "rfsitl/common/net_frame.hpp"
#include "rfsitl/common/types.hpp"

namespace rfsitl::phy {

/// What the TX path puts on the air besides the net frame: a serial number that
/// lets the engine match each decode to the transmission it came from.
struct FrameTag {
  NodeId src = 0;
  NodeId dst = 0;
  std::uint32_t serial = 0;  ///< unique per transmitter
};

/// One decode attempt of the RX path.
struct RxEvent {
  FrameTag tag;                           ///< valid only if header_valid
  std::span<const std::uint8_t> payload;  ///< valid only during the callback
  bool header_valid = false;
  bool payload_valid = false;  ///< CRC passed
  float rssi_db = 0.0F;
  float evm_db = 0.0F;
  /// Constellation/frame symbols of this decode, valid only during the callback.
  std::span<const cf32> symbols;
};

/// Receives RX events synchronously, on the thread that runs Transceiver::receive().
class RxHandler {
 public:
  virtual ~RxHandler() = default;
  virtual void on_rx(const RxEvent& event) = 0;
};

class Transceiver {
 public:
  virtual ~Transceiver() = default;

  /// Largest payload (net frame payload bytes, without src/dst) one frame can carry.
  virtual std::size_t max_payload() const = 0;

  /// Number of samples the frame for a `payload_bytes` payload occupies on the air.
  virtual std::size_t frame_samples(std::size_t payload_bytes) const = 0;

  /// Lowest SNR (dB, signal power over noise power in the sample bandwidth) at
  /// which this PHY decodes reliably; the engine uses it only to name the reason
  /// of a loss, never to decide one.
  virtual double sensitivity_snr_db() const = 0;

  /// True while a frame is being transmitted.
  virtual bool tx_busy() const = 0;

  /// Starts transmitting a frame at the next sample written by transmit() and
  /// returns its length in samples (== frame_samples(payload.size())).
  /// Preconditions: !tx_busy(); payload.size() <= max_payload().
  virtual std::size_t start_frame(const FrameTag& tag, std::span<const std::uint8_t> payload) = 0;

  /// Writes exactly out.size() transmitted samples (zeros once the frame is over)
  /// and returns how many of them carry signal, counted from the start of `out`.
  virtual std::size_t transmit(std::span<cf32> out) = 0;

  /// Feeds received samples to the RX path; decodes are reported to `handler`
  /// before this returns.
  virtual void receive(std::span<const cf32> in, RxHandler& handler) = 0;

  /// Abandons whatever the RX path was receiving and starts afresh, as a
  /// half-duplex radio's receiver does when its T/R switch returns to receive.
  virtual void reset_receiver() = 0;

  /// True while the RX path is inside a frame it has detected (so it must keep
  /// getting samples even if nothing is on the air).
  virtual bool rx_busy() const = 0;

  /// Samples the RX path needs after a frame's last sample before it reports
  /// the decode (filter delays).
  virtual std::size_t rx_latency_samples() const = 0;

  /// Called once at the start of every tick, before any other call in it, with
  /// the tick's index and the virtual time of its first sample. A transceiver
  /// in another process uses it to stay in lock-step (and to rejoin); the
  /// built-in ones ignore it.
  virtual void begin_tick(std::uint64_t /*tick*/, SampleTime /*time*/) {}

  /// True when the work runs in another process and every call may block on a
  /// round trip: the engine then gives each such transceiver a worker of its
  /// own, so that their round trips overlap.
  virtual bool remote() const { return false; }
};

}  // namespace rfsitl::phy
