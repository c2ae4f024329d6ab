#pragma once
/// Paces lock-step ticks. In real-time mode tick k may start once the wall
/// clock reaches start + k * B / (fs * speed); lateness is measured, never hidden.
/// In virtual-time mode ticks run back to back.
#include <chrono>
#include <cstdint>

namespace rfsitl::engine {

class TickClock {
 public:
  /// Preconditions: sample_rate_hz > 0, tick_samples > 0, speed > 0.
  TickClock(double sample_rate_hz, std::uint32_t tick_samples, double speed, bool real_time);

  /// Blocks until tick `k` is due (real time) and records how late it started.
  void wait_for_tick(std::uint64_t k);

  /// Lag of the latest tick (seconds the wall clock is ahead of the schedule; >= 0).
  double lag_s() const { return lag_s_; }
  /// Worst lag seen so far.
  double max_lag_s() const { return max_lag_s_; }
  /// Ticks that started more than one tick period late.
  std::uint64_t late_ticks() const { return late_ticks_; }
  /// Wall seconds since the first tick.
  double elapsed_wall_s() const;

 private:
  using Clock = std::chrono::steady_clock;
  std::chrono::duration<double> tick_period_;  // wall time per tick
  bool real_time_;
  bool started_ = false;
  Clock::time_point start_;
  double lag_s_ = 0.0;
  double max_lag_s_ = 0.0;
  std::uint64_t late_ticks_ = 0;
};

}  // namespace rfsitl::engine
