#pragma once
/// The buffers between a SoapySDR application (wall clock, reads late or
/// never writes) and the emulator's ticks, without the connection: NodeStreamer
/// feeds on_tick() from its pump thread; unit tests feed it directly.
///
///   on_tick(t, rx, tx): RX chunk [t - rx.size(), t) queued (the oldest
///                       dropped beyond the RX capacity: overflow),
///                       TX [t, t + tx.size()) taken from the scheduled bursts.
///
/// Times are virtual sample indexes (SampleTime). Results are SoapySDR's codes
/// (SOAPY_SDR_TIMEOUT, ...). Thread safety: every method may be called from
/// any thread; one mutex guards the buffers.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <span>
#include <vector>

#include "rfsitl/common/types.hpp"
#include "signal_path.hpp"

namespace rfsitl::soapy {

/// A readStreamStatus() event of the TX stream.
struct TxEvent {
  int code = 0;         ///< SOAPY_SDR_TIME_ERROR (late burst) or SOAPY_SDR_UNDERFLOW
  SampleTime time = 0;  ///< the burst's requested start, or where samples ran out
};

class StreamBuffers {
 public:
  /// `rx_capacity`, `tx_capacity`: samples held at most each way.
  StreamBuffers(double sample_rate_hz, std::size_t rx_capacity, std::size_t tx_capacity);

  void set_rx_tuning(const PathTuning& t);
  void set_tx_tuning(const PathTuning& t);

  /// RX samples are kept only while active; activating empties the buffer so
  /// that the first read is recent.
  void set_rx_active(bool active);

  /// Up to `out.size()` contiguous samples, the first at `time` (samples).
  /// Returns the count, or SOAPY_SDR_OVERFLOW once after samples were dropped,
  /// SOAPY_SDR_TIMEOUT when nothing came within `timeout_us`, and
  /// SOAPY_SDR_STREAM_ERROR once closed and the buffer is empty: at once the
  /// first time, then after min(timeout, 100 ms) (callers that retry on
  /// errors must not spin).
  int read(std::span<cf32> out, SampleTime& time, long timeout_us);

  /// Queues `in` for transmission: from `*time` (samples) when given, else
  /// right after the previous write's samples, or from the next tick when
  /// those have all been sent. `end_burst`: the burst ends with these
  /// samples, so running out afterwards is no underflow. Returns how many
  /// samples were taken (a late burst is taken and dropped, reported by
  /// read_event()), or SOAPY_SDR_TIMEOUT when the queue stayed full for
  /// `timeout_us`, or SOAPY_SDR_STREAM_ERROR once closed.
  int write(std::span<const cf32> in, const SampleTime* time, bool end_burst, long timeout_us);

  /// The next TX event (late burst, underflow): 0 with `event` set, or
  /// SOAPY_SDR_TIMEOUT, or SOAPY_SDR_STREAM_ERROR once closed. At most the
  /// latest 1024 events are kept.
  int read_event(TxEvent& event, long timeout_us);

  /// One tick of the emulator at time `t`: `rx` are the samples of [t -
  /// rx.size(), t); `tx` is filled with [t, t + tx.size()).
  void on_tick(SampleTime t, std::span<const cf32> rx, std::span<cf32> tx);
  /// The emulator is gone: waiting calls return, later ones fail.
  void close();
  /// A new connection (an emulator that came back) whose ticks start at `t`:
  /// what was buffered for the old one's virtual time is dropped (RX chunks,
  /// queued bursts, a pending overflow), and calls work again. Tunings, the
  /// RX stream's state, TX events and the counters stay.
  void reopen(SampleTime t);

  /// The start of the latest tick (virtual samples); 0 before the first.
  SampleTime now() const;
  /// now(), but before the first tick it waits up to `timeout_us` for it, so
  /// that a time read right after the connection is the emulator's and not
  /// 0. False (and `t` unchanged) when none came in time, or the connection
  /// closed first.
  bool now_after_first_tick(SampleTime& t, long timeout_us);
  /// False once close() was called.
  bool connected() const;

  std::uint64_t overflows() const { return overflows_.load(); }
  std::uint64_t underflows() const { return underflows_.load(); }
  std::uint64_t late_bursts() const { return late_bursts_.load(); }

 private:
  struct Chunk {
    SampleTime time = 0;  ///< time of samples[used] (bursts) or samples[0] (RX)
    std::vector<cf32> samples;
    std::size_t used = 0;
  };

  // Under mutex_.
  void take_rx(SampleTime t, std::span<const cf32> rx);
  void build_tx(SampleTime t, std::span<cf32> out);
  void push_event(const TxEvent& e);

  const double sample_rate_hz_;
  const std::size_t rx_capacity_, tx_capacity_;

  mutable std::mutex mutex_;
  std::condition_variable changed_;  // new RX chunk, TX room, TX event or closed
  PathTuning rx_tuning_, tx_tuning_;
  bool rx_active_ = false;
  std::deque<Chunk> rx_;
  std::size_t rx_buffered_ = 0;
  bool overflow_pending_ = false;
  std::deque<Chunk> tx_;  // bursts in order of start time
  std::size_t tx_queued_ = 0;
  SampleTime tx_floor_ = 0;  // earliest time still placeable: the next tick's start
  SampleTime tx_next_ = 0;   // where an untimed write continues
  bool in_burst_ = false;    // the application's burst continues (no END_BURST yet)
  std::deque<TxEvent> events_;
  SampleTime now_ = 0;
  bool ticked_ = false;  // a tick came: now_ is the emulator's time
  bool closed_ = false;
  bool error_reported_ = false;  // read() returned SOAPY_SDR_STREAM_ERROR once

  std::atomic<std::uint64_t> overflows_{0}, underflows_{0}, late_bursts_{0};
};

}  // namespace rfsitl::soapy
