#pragma once
/// The SoapySDR module's engine: one node of a running emulator, held through
/// the external-transceiver protocol (role "samples", wire_protocol.hpp), with
/// a thread of its own that answers every tick from buffers. A SoapySDR
/// application lives on the wall clock and may read late or never write; the
/// emulator must never wait for it, so the application only ever touches the
/// buffers:
///
///   tick k (time t, B samples) --pump thread--> RX chunk [t-B, t) queued,
///                                               TX [t, t+B) taken from the
///                                               scheduled bursts, answered.
///
/// Times are virtual sample indexes (SampleTime) inside, nanoseconds at the
/// SoapySDR surface (ns = samples * 1e9 / fs). Thread safety: every public
/// method may be called from any thread; one mutex guards the buffers.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "rfsitl/common/types.hpp"
#include "rfsitl/external/external_client.hpp"

namespace rfsitl::soapy {

/// What the application set for one direction: where it is tuned relative to
/// the emulator's carrier, and its gain.
struct PathTuning {
  bool in_band = true;     ///< false: tuned outside [carrier - fs/2, carrier + fs/2): silence
  double offset_hz = 0.0;  ///< tuned frequency - carrier, |offset| < fs/2 when in_band
  double gain_db = 0.0;    ///< amplitude scale 10^(gain/20)
};

/// A readStreamStatus() event of the TX stream.
struct TxEvent {
  int code = 0;         ///< SOAPY_SDR_TIME_ERROR (late burst) or SOAPY_SDR_UNDERFLOW
  SampleTime time = 0;  ///< the burst's requested start, or where samples ran out
};

class NodeStreamer {
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

  double sample_rate_hz() const { return welcome_.sample_rate_hz; }
  std::uint32_t tick_samples() const { return welcome_.tick_samples; }

  long long to_ns(SampleTime t) const;
  SampleTime to_samples(long long ns) const;

  void set_rx_tuning(const PathTuning& t);
  void set_tx_tuning(const PathTuning& t);

  /// RX samples are kept only while active; activating empties the buffer so
  /// that the first read is recent.
  void set_rx_active(bool active);

  /// Up to `out.size()` contiguous samples, the first at `time` (samples).
  /// Returns the count, or SOAPY_SDR_OVERFLOW once after samples were dropped,
  /// SOAPY_SDR_TIMEOUT when nothing came within `timeout_us`, and
  /// SOAPY_SDR_STREAM_ERROR once the emulator is gone and the buffer is empty.
  int read(std::span<cf32> out, SampleTime& time, long timeout_us);

  /// Queues `in` for transmission: from `*time` (samples) when given, else
  /// right after the previous write's samples, or from the next tick when
  /// those have all been sent. `end_burst`: the burst ends with these samples, so running
  /// out afterwards is no underflow. Returns how many samples were taken (a
  /// late burst is taken and dropped, reported by read_event()), or
  /// SOAPY_SDR_TIMEOUT when the queue stayed full for `timeout_us`, or
  /// SOAPY_SDR_STREAM_ERROR when the emulator is gone.
  int write(std::span<const cf32> in, const SampleTime* time, bool end_burst, long timeout_us);

  /// The next TX event (late burst, underflow): 0 with `event` set, or
  /// SOAPY_SDR_TIMEOUT, or SOAPY_SDR_STREAM_ERROR when the emulator is gone.
  int read_event(TxEvent& event, long timeout_us);

  /// The start of the latest tick the emulator sent (virtual samples).
  SampleTime now() const;
  /// False once the emulator closed the connection (stopped, or dropped us).
  bool connected() const;

  std::uint64_t overflows() const { return overflows_.load(); }
  std::uint64_t underflows() const { return underflows_.load(); }
  std::uint64_t late_bursts() const { return late_bursts_.load(); }

 private:
  struct Chunk {
    SampleTime time = 0;
    std::vector<cf32> samples;
    std::size_t used = 0;
  };
  struct Burst {
    SampleTime start = 0;  ///< time of samples[used]
    std::vector<cf32> samples;
    std::size_t used = 0;
  };

  void pump();
  // Pump thread, under mutex_: the tick's RX chunk and TX samples.
  void take_rx(const external::Tick& tick);
  void build_tx(SampleTime t, std::span<cf32> out);
  void close_with(const std::string& why);

  Settings settings_;
  external::ExternalClient client_;  // pump thread only, after construction
  external::Welcome welcome_;
  std::size_t rx_capacity_ = 0;  // samples
  std::size_t tx_capacity_ = 0;  // samples

  mutable std::mutex mutex_;
  std::condition_variable changed_;  // new RX chunk, TX room, TX event or closed
  PathTuning rx_tuning_, tx_tuning_;
  bool rx_active_ = false;
  std::deque<Chunk> rx_;
  std::size_t rx_buffered_ = 0;
  bool overflow_pending_ = false;
  std::deque<Burst> tx_;  // in order of start time
  std::size_t tx_queued_ = 0;
  SampleTime tx_floor_ = 0;  // earliest time still placeable: the next tick's start
  SampleTime tx_next_ = 0;   // where an untimed write continues
  bool in_burst_ = false;    // the application's burst continues (no END_BURST yet)
  std::deque<TxEvent> events_;
  SampleTime now_ = 0;
  bool closed_ = false;

  std::atomic<bool> stopping_{false};
  std::atomic<std::uint64_t> overflows_{0}, underflows_{0}, late_bursts_{0};
  std::thread thread_;
};

}  // namespace rfsitl::soapy
