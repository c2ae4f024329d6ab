#pragma once
/// Paces lock-step ticks in real-time mode. Tick k holds the samples of virtual
/// interval [k B, (k+1) B) / fs; it is computed once the wall clock has reached
/// the end of that interval (start + (k+1) B / (fs * speed)), so nothing it
/// decodes reaches an agent before it could have on the air. Lateness is
/// measured, never hidden. In virtual-time mode ticks run back to back.
#include <atomic>
#include <chrono>
#include <cstdint>

#include "rfsitl/common/types.hpp"

namespace rfsitl::engine {

class TickClock {
 public:
  /// Preconditions: sample_rate_hz > 0, tick_samples > 0, speed > 0.
  TickClock(double sample_rate_hz, std::uint32_t tick_samples, double speed, bool real_time);

  bool real_time() const { return real_time_; }

  /// Starts the schedule: virtual time 0 is now. Called once, before wait_for_tick.
  void start();

  /// Blocks until tick `k` is due (real time) and records how late it is.
  void wait_for_tick(std::uint64_t k);

  /// Virtual time (samples) the wall clock has reached; 0 before start() and in
  /// virtual-time mode. Thread-safe: the I/O thread stamps arriving frames with it.
  SampleTime wall_now_samples() const;

  /// Lag of the latest tick (seconds the wall clock is past the tick's due time).
  double lag_s() const { return lag_s_; }
  /// Worst lag seen so far.
  double max_lag_s() const { return max_lag_s_; }
  /// Ticks that were computed more than one tick period after they were due.
  std::uint64_t late_ticks() const { return late_ticks_; }
  /// Wall seconds since start().
  double elapsed_wall_s() const;

 private:
  using Clock = std::chrono::steady_clock;
  Clock::time_point start_time() const;

  double samples_per_wall_s_;
  std::chrono::duration<double> tick_period_;  // wall time per tick
  bool real_time_;
  std::atomic<Clock::rep> start_ticks_{0};  // Clock ticks of start(); 0 = not started
  double lag_s_ = 0.0;
  double max_lag_s_ = 0.0;
  std::uint64_t late_ticks_ = 0;
};

}  // namespace rfsitl::engine
