#pragma once
// Internal to the DSSS receiver: what every listened code shares. Keeps the
// raw samples, the chip-integrated samples y (the rectangular chip's matched
// filter) and, per sample, the received energy that normalizes the detector.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "rfsitl/common/types.hpp"
#include "sliding_window.hpp"

namespace rfsitl::phy::dsss::detail {

class FrontEnd {
 public:
  /// y keeps `y_history` samples before each block, the energy `e_history`.
  void configure(unsigned samples_per_chip, std::size_t period, std::size_t energy_periods,
                 std::size_t y_history, std::size_t e_history, std::size_t max_block);
  void reset();

  /// Appends a block of at most max_block samples.
  void ingest(std::span<const cf32> x);

  /// Absolute index after the newest sample.
  std::int64_t end() const { return y_.end(); }

  /// y[t]; the previous y_history samples are readable behind it.
  const cf32* y(std::int64_t t) const { return y_.at(t); }

  /// Mean power per sample over the current partial code period and the
  /// `energy_periods` complete periods before it (fewer just after a reset).
  /// Summed period by period, never by subtracting, so a strong burst leaves no
  /// rounding residue behind that could make silence look like a signal.
  const float* mean_power(std::int64_t t) const { return e_.at(t); }

 private:
  unsigned samples_per_chip_ = 1;
  std::size_t period_ = 1;
  SlidingWindow<cf32> x_;
  SlidingWindow<cf32> y_;
  SlidingWindow<float> e_;
  std::vector<float> period_energy_;  // ring of the last complete periods
  std::size_t ring_pos_ = 0;
  float complete_ = 0.0F;           // sum of the ring
  float partial_ = 0.0F;            // energy of the current period so far
  std::size_t phase_ = 0;           // samples of the current period so far
  std::size_t complete_count_ = 0;  // complete periods in the ring (up to its size)
};

}  // namespace rfsitl::phy::dsss::detail
