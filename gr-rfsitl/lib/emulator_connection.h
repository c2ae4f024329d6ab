#pragma once
/// Per-process shared state of one external node: the emulator link and the
/// transmit buffer between emulator_sink and emulator_source.
#include <gnuradio/gr_complex.h>
#include <gnuradio/logger.h>
#include <gnuradio/thread/thread.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>

#include "rfsitl/external/client/external_client.hpp"

namespace gr::rfsitl {

/// One external node (socket path, node id) in this process. The source and
/// the sink of a node hold the same instance (get() keeps a registry of weak
/// pointers), so they share one connection: the emulator sees one node.
///
/// Threading: client() belongs to the emulator_source's thread; the transmit
/// buffer is safe between the sink's thread (put_tx/release) and the source's
/// thread (take_tx); buffered() and capacity() may be called from anywhere.
class emulator_connection {
 public:
  /// The instance for (socket_path, node_id), created on first use. Throws
  /// std::invalid_argument for an empty path or a node id outside 1..250.
  static std::shared_ptr<emulator_connection> get(const std::string& socket_path, int node_id);

  emulator_connection(const std::string& socket_path, int node_id);
  emulator_connection(const emulator_connection&) = delete;
  emulator_connection& operator=(const emulator_connection&) = delete;

  const std::string& socket_path() const { return socket_path_; }
  int node_id() const { return node_id_; }
  /// "node N (PATH)", for log messages.
  const std::string& label() const { return label_; }

  // ---- source side ----

  /// Registers the node's only source and creates its client. Throws
  /// std::runtime_error if another emulator_source already serves this node:
  /// two would join as one node.
  void attach_source(int handshake_timeout_ms);
  void detach_source();
  /// The emulator link; valid between attach_source() and detach_source().
  ::rfsitl::external::ExternalClient& client() { return *client_; }
  /// Resizes the buffer bound to the emulator's sample rate (from kWelcome).
  void set_sample_rate(double sample_rate_hz, std::uint32_t tick_samples);
  /// Moves up to `max` released samples to `out`; returns how many.
  std::size_t take_tx(gr_complex* out, std::size_t max);
  /// Marks the source as ended for good (or running again): a sink waiting
  /// for space gives up instead of blocking forever.
  void set_finished(bool finished);

  // ---- sink side ----

  /// Registers the node's only sink with its buffer bound in seconds of
  /// samples. Throws std::runtime_error if another emulator_sink already
  /// feeds this node: two would interleave their samples.
  void attach_sink(double buffer_seconds);
  void detach_sink();
  /// Appends up to `n` samples, waiting while the buffer is full. The wait is
  /// a boost interruption point, so stopping the flowgraph ends it. Returns the
  /// number appended (at least 1), or 0 once the source has finished.
  std::size_t put_tx(const gr_complex* in, std::size_t n);
  /// Makes every appended sample available to take_tx.
  void release();

  std::size_t buffered() const;
  std::size_t capacity() const;

 private:
  std::size_t bound_locked() const;

  const std::string socket_path_;
  const int node_id_;
  const std::string label_;
  gr::logger logger_;
  std::unique_ptr<::rfsitl::external::ExternalClient> client_;

  mutable gr::thread::mutex mutex_;
  gr::thread::condition_variable space_cv_;  // signalled when samples leave or on finish
  std::deque<gr_complex> tx_;
  std::size_t released_ = 0;  // leading samples of tx_ the source may take
  double sample_rate_hz_ = 1e6;
  std::uint32_t tick_samples_ = 0;
  double buffer_seconds_ = 0.5;
  bool finished_ = false;
  bool source_attached_ = false;
  bool sink_attached_ = false;
  bool warned_no_source_ = false;
};

}  // namespace gr::rfsitl
