#include "rfsitl/engine/tick_clock.hpp"

#include <algorithm>
#include <thread>

namespace rfsitl::engine {

TickClock::TickClock(double sample_rate_hz, std::uint32_t tick_samples, double speed,
                     bool real_time)
    : tick_period_(static_cast<double>(tick_samples) / (sample_rate_hz * speed)),
      real_time_(real_time) {}

void TickClock::wait_for_tick(std::uint64_t k) {
  if (!started_) {
    start_ = Clock::now();
    started_ = true;
  }
  if (!real_time_) return;
  const auto due =
      start_ + std::chrono::duration_cast<Clock::duration>(tick_period_ * static_cast<double>(k));
  auto now = Clock::now();
  if (now < due) {
    std::this_thread::sleep_until(due);
    now = Clock::now();
  }
  lag_s_ = std::max(0.0, std::chrono::duration<double>(now - due).count());
  max_lag_s_ = std::max(max_lag_s_, lag_s_);
  if (lag_s_ > tick_period_.count()) ++late_ticks_;
}

double TickClock::elapsed_wall_s() const {
  return started_ ? std::chrono::duration<double>(Clock::now() - start_).count() : 0.0;
}

}  // namespace rfsitl::engine
