#include "rfsitl/engine/tick_clock.hpp"

#include <algorithm>
#include <cmath>
#include <thread>

namespace rfsitl::engine {

TickClock::TickClock(double sample_rate_hz, std::uint32_t tick_samples, double speed,
                     bool real_time)
    : samples_per_wall_s_(sample_rate_hz * speed),
      tick_period_(static_cast<double>(tick_samples) / (sample_rate_hz * speed)),
      real_time_(real_time) {}

void TickClock::start() {
  // steady_clock never reads 0 after boot, so 0 can mean "not started".
  start_ticks_.store(Clock::now().time_since_epoch().count(), std::memory_order_release);
}

TickClock::Clock::time_point TickClock::start_time() const {
  return Clock::time_point(Clock::duration(start_ticks_.load(std::memory_order_acquire)));
}

void TickClock::wait_for_tick(std::uint64_t k) {
  if (!real_time_) return;
  const auto due = start_time() + std::chrono::duration_cast<Clock::duration>(
                                      tick_period_ * static_cast<double>(k + 1));
  auto now = Clock::now();
  if (now < due) {
    std::this_thread::sleep_until(due);
    now = Clock::now();
  }
  lag_s_ = std::max(0.0, std::chrono::duration<double>(now - due).count());
  max_lag_s_ = std::max(max_lag_s_, lag_s_);
  if (lag_s_ > tick_period_.count()) ++late_ticks_;
}

SampleTime TickClock::wall_now_samples() const {
  if (!real_time_ || start_ticks_.load(std::memory_order_acquire) == 0) return 0;
  const double wall = std::chrono::duration<double>(Clock::now() - start_time()).count();
  return static_cast<SampleTime>(std::floor(wall * samples_per_wall_s_));
}

double TickClock::elapsed_wall_s() const {
  if (start_ticks_.load(std::memory_order_acquire) == 0) return 0.0;
  return std::chrono::duration<double>(Clock::now() - start_time()).count();
}

}  // namespace rfsitl::engine
