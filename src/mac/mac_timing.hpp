#pragma once
// Internal to the MACs: their times as whole ticks (mac.hpp says why).
#include <algorithm>
#include <cmath>
#include <cstddef>

#include "rfsitl/mac/mac.hpp"

namespace rfsitl::mac::detail {

/// `us` microseconds as ticks, rounded up, at least `at_least`.
inline std::size_t ticks_of_us(double us, const MacContext& c, std::size_t at_least = 1) {
  const double samples = us * 1e-6 * c.sample_rate_hz;
  const auto ticks =
      static_cast<std::size_t>(std::ceil(samples / static_cast<double>(c.tick_samples) - 1e-9));
  return std::max(ticks, at_least);
}

/// `ticks` ticks in microseconds (for what the banner prints).
inline double us_of_ticks(std::size_t ticks, const MacContext& c) {
  return static_cast<double>(ticks * c.tick_samples) / c.sample_rate_hz * 1e6;
}

/// The largest radio payload (bytes) whose frame lasts at most `samples`, up
/// to c.radio_max_payload; 0 when not even an empty frame fits.
inline std::size_t largest_payload_within(std::size_t samples, const MacContext& c) {
  if (c.frame_samples(0) > samples) return 0;
  std::size_t lo = 0;
  std::size_t hi = c.radio_max_payload;
  while (lo < hi) {  // frame_samples grows with the payload
    const std::size_t mid = lo + (hi - lo + 1) / 2;
    if (c.frame_samples(mid) <= samples) {
      lo = mid;
    } else {
      hi = mid - 1;
    }
  }
  return lo;
}

}  // namespace rfsitl::mac::detail
