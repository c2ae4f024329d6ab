#pragma once
/// The SoapySDR module's engine: one node of a running emulator, held through
/// the external-transceiver protocol (role "samples", wire_protocol.hpp), with
/// a thread of its own that answers every tick from StreamBuffers. A SoapySDR
/// application lives on the wall clock and may read late or never write; the
/// emulator must never wait for it, so the application only ever touches the
/// buffers:
///
///   tick k (time t, B samples) --pump thread--> StreamBuffers::on_tick(),
///                                               TX [t, t+B) answered.
///
/// Times are virtual sample indexes (SampleTime) inside, nanoseconds at the
/// SoapySDR surface (ns = samples * 1e9 / fs). Thread safety: as StreamBuffers.
#include <atomic>
#include <string>
#include <thread>

#include "rfsitl/common/types.hpp"
#include "rfsitl/external/external_client.hpp"
#include "stream_buffers.hpp"

namespace rfsitl::soapy {

namespace detail {

/// The connection, made before StreamBuffers is sized from its welcome (a
/// base class, because bases are constructed before members).
struct ConnectedClient {
  ConnectedClient(const std::string& socket_path, NodeId node_id, const std::string& program)
      : client({socket_path, node_id, "samples", program, 5000}), welcome(client.connect()) {}
  external::ExternalClient client;  // pump thread only, after construction
  external::Welcome welcome;
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
  };

  /// Connects as node `settings.node_id` (claiming it: a process already
  /// connected as that node is replaced by the emulator) and starts the pump
  /// thread. Throws std::runtime_error from ExternalClient::connect().
  explicit NodeStreamer(Settings settings);
  /// Stops the pump and disconnects (the node goes silent in the emulator).
  ~NodeStreamer();
  NodeStreamer(const NodeStreamer&) = delete;
  NodeStreamer& operator=(const NodeStreamer&) = delete;

  double sample_rate_hz() const { return welcome.sample_rate_hz; }
  std::uint32_t tick_samples() const { return welcome.tick_samples; }

  long long to_ns(SampleTime t) const;
  SampleTime to_samples(long long ns) const;

 private:
  void pump();
  void close_with(const std::string& why);

  Settings settings_;
  std::atomic<bool> stopping_{false};
  std::thread thread_;
};

}  // namespace rfsitl::soapy
