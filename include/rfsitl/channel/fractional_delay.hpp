#pragma once
/// A delay of a fractional number of samples as a short FIR filter, for the
/// paths of dispersive links (channel.hpp).
#include <array>
#include <cstddef>
#include <cstdint>

namespace rfsitl::channel {

/// x(t - d) ~= sum_{l < count} taps[l] x[t - first_lag - l] for a signal
/// band-limited below fs / 2.
struct FractionalDelay {
  static constexpr std::size_t kMaxTaps = 16;
  std::uint32_t first_lag = 0;  ///< samples, >= 0
  std::uint32_t count = 0;      ///< taps used, 1..kMaxTaps
  std::array<float, kMaxTaps> taps{};
};

/// The filter for a delay of `delay_samples` (>= 0, below 2^31): a
/// Kaiser-windowed sinc over the kMaxTaps samples around the delay, normalised
/// to unit gain at DC. A delay within 1e-3 of a whole number is that whole
/// number: one tap of 1. The filter never reads ahead of the current sample (a
/// channel cannot see the future): a delay of d < 7 whole samples gets the
/// 2 d + 2 taps around it, so the error grows there (measured in
/// fractional_delay_test.cpp). Pure.
FractionalDelay fractional_delay(double delay_samples);

}  // namespace rfsitl::channel
