#pragma once
/// The receive half of an rfsitl external node (role "samples").
#include <gnuradio/rfsitl/api.h>
#include <gnuradio/sync_block.h>

#include <cstdint>
#include <memory>
#include <string>

namespace gr::rfsitl {

/// Joins an rfsitl emulator run as node `node_id` over the Unix SOCK_SEQPACKET
/// socket `socket_path` and outputs the node's received baseband samples
/// (gr_complex at the emulator's sample rate, noise at unit power).
///
/// The block paces the flowgraph: it produces samples only as the emulator's
/// ticks arrive, so no throttle is needed. Every tick it answers at once with
/// up to one tick of transmit samples taken from the emulator_sink of the same
/// (socket_path, node_id) in this process (none: the node is silent).
///
/// Stream tags: `rx_time` (UHD convention, tuple (uint64 full seconds, double
/// fractional seconds) of virtual time since the emulator started) and
/// `rx_rate` (double, samples/s) on the first sample after joining, after
/// rejoining and after missed ticks. Between two tags the stream is
/// sample-contiguous in virtual time.
///
/// Connection handling: connects in the first work() call, retrying for up to
/// `reconnect_ms` while the emulator is not up; waits without a timeout for
/// the first tick (a run may wait for all its external nodes to join); rejoins
/// when the emulator drops the node (e.g. it answered too late) or, once
/// ticking, sends no tick for `timeout_ms`; when no connection succeeds within
/// `reconnect_ms`, returns WORK_DONE so the flowgraph can end. tb.stop() takes
/// effect within about 0.1 s (the handshake itself, normally instant, waits at
/// most min(timeout_ms, 5 s)).
///
/// One emulator_source per (socket_path, node_id) and process: make() throws
/// std::runtime_error for a second one, which would join as the same node.
class RFSITL_API emulator_source : virtual public gr::sync_block {
 public:
  using sptr = std::shared_ptr<emulator_source>;

  /// \param socket_path the emulator's external-node socket
  /// \param node_id     this node's id, 1..254
  /// \param timeout_ms  tick silence (once ticking) after which the node rejoins
  /// \param reconnect_ms how long to keep trying to (re)connect before ending
  static sptr make(const std::string& socket_path, int node_id, int timeout_ms = 2000,
                   int reconnect_ms = 20000);

  /// True while joined (after kWelcome, until the connection ends).
  virtual bool connected() const = 0;
  /// True once the block gave up reconnecting and returned WORK_DONE.
  virtual bool finished() const = 0;
  /// Emulator sample rate in Hz from the last welcome; 0 before the first join.
  virtual double sample_rate() const = 0;
  /// Samples per tick (B) from the last welcome; 0 before the first join.
  virtual int tick_samples() const = 0;
  /// Ticks answered since the block was created.
  virtual std::uint64_t ticks() const = 0;
  /// Successful joins (1 after the first connection, +1 per rejoin).
  virtual std::uint64_t joins() const = 0;
  /// Ticks that did not follow the previous one within a connection.
  virtual std::uint64_t discontinuities() const = 0;
  /// Transmit samples handed to the emulator (excluding its zero padding).
  virtual std::uint64_t tx_samples_sent() const = 0;
};

}  // namespace gr::rfsitl
