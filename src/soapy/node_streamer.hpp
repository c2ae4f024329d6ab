#pragma once
/// The SoapySDR module's engine: one node of a running emulator, held through
/// the external-transceiver protocol (role "samples", wire_protocol.hpp), with
/// a thread of its own that answers every tick from StreamBuffers. A SoapySDR
/// application lives on the wall clock and may read late or never write; the
/// emulator must never wait for it, so the application only ever touches the
/// buffers:
///
///   tick k (time t, B samples) --pump thread--> StreamBuffers::on_tick(),
///                                               TX [t, t+B) answered with
///                                               the overflow count (TxReport).
///
/// When the emulator goes away (stops, restarts, drops the node), reads fail
/// with SOAPY_SDR_STREAM_ERROR and the pump keeps trying to join the same
/// socket and node again; a new emulator there with the same sample rate and
/// tick takes the device back, its virtual time from its first tick on.
///
/// Times are virtual sample indexes (SampleTime) inside, nanoseconds at the
/// SoapySDR surface (ns = samples * 1e9 / fs). Thread safety: as StreamBuffers.
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

#include "rfsitl/common/types.hpp"
#include "rfsitl/external/client/external_client.hpp"
#include "stream_buffers.hpp"

namespace rfsitl::soapy {

namespace detail {

/// The connection, made before StreamBuffers is sized from its welcome (a
/// base class, because bases are constructed before members).
struct ConnectedClient {
  ConnectedClient(const std::string& socket_path, NodeId node_id, const std::string& program,
                  bool exclusive)
      : client({socket_path, node_id, "samples", program, 5000, exclusive}),
        welcome(client.connect()) {}
  external::ExternalClient client;  // pump thread only, after construction
  const external::Welcome welcome;  // the first one: a rejoin must match its rate and tick
};

}  // namespace detail

class NodeStreamer : private detail::ConnectedClient, public StreamBuffers {
 public:
  struct Settings {
    std::string socket_path;
    NodeId node_id = 0;
    std::string program = "soapy";
    /// RX buffer in virtual seconds; beyond it the oldest samples are dropped
    /// and the next read reports SOAPY_SDR_OVERFLOW.
    double rx_buffer_s = 1.0;
    /// TX samples queued ahead at most (in ticks); a writer beyond it waits.
    std::size_t tx_queue_ticks = 64;
    /// Take the node over from a process that holds it (the emulator drops
    /// that one); else the emulator refuses the claim while it is held.
    bool takeover = false;
  };

  /// Connects as node `settings.node_id` and starts the pump thread. Throws
  /// std::runtime_error from ExternalClient::connect() (ConnectRejected when
  /// the emulator refuses, e.g. the node is held and `takeover` is false).
  explicit NodeStreamer(Settings settings);
  /// Stops the pump and disconnects (the node goes silent in the emulator).
  ~NodeStreamer();
  NodeStreamer(const NodeStreamer&) = delete;
  NodeStreamer& operator=(const NodeStreamer&) = delete;

  double sample_rate_hz() const { return welcome.sample_rate_hz; }
  std::uint32_t tick_samples() const { return welcome.tick_samples; }

  long long to_ns(SampleTime t) const;
  SampleTime to_samples(long long ns) const;

  /// Times the device joined an emulator again after losing one.
  std::uint64_t rejoins() const { return rejoins_.load(); }
  /// "connected", "rejoining: <why the connection ended>" or "stopped: <why
  /// it cannot rejoin>", for getHardwareInfo.
  std::string link_state() const;

 private:
  void pump();
  /// The connection ended: readers get SOAPY_SDR_STREAM_ERROR; the pump
  /// tries to rejoin.
  void lose(const std::string& why);
  /// Tries to join again every kRejoinPauseMs (exclusively: a program that
  /// took the node over keeps it) until it did (true) or must not (false:
  /// stopping, or the new emulator's rate or tick differ from this device's).
  bool rejoin();
  void set_state(std::string state);

  Settings settings_;
  std::atomic<bool> stopping_{false};
  std::atomic<std::uint64_t> rejoins_{0};
  bool reopen_at_next_tick_ = false;     // pump thread only
  std::uint64_t overflows_at_join_ = 0;  // pump thread only: the report counts from the welcome
  mutable std::mutex state_mutex_;
  std::string state_ = "connected";
  std::thread thread_;
};

}  // namespace rfsitl::soapy
