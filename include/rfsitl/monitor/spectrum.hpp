#pragma once
/// Averaged power spectrum of a sample stream (Welch's method, Hann window,
/// no overlap), for the dashboard's spectrum and waterfall.
#include <cstddef>
#include <span>
#include <vector>

#include "rfsitl/common/types.hpp"

namespace rfsitl::monitor {

/// In-place radix-2 decimation-in-time FFT. Precondition: x.size() is a power of two.
void fft_in_place(std::span<cf32> x);

class SpectrumAverager {
 public:
  /// Precondition: bins is a power of two >= 8.
  explicit SpectrumAverager(std::size_t bins);

  /// Appends samples; every full block of `bins` samples adds one periodogram.
  void add(std::span<const cf32> samples);

  /// Forgets samples that do not yet fill a block (the stream had a gap).
  void discard_partial_block() { filled_ = 0; }

  /// Blocks averaged since the last take().
  std::size_t blocks() const { return blocks_; }

  /// Power per bin in dB (10 log10 of the mean |X_k|^2 / sum(w^2)), from
  /// -fs/2 to fs/2 (DC in the middle), and restarts the average. Empty when no
  /// block is complete. With unit-power white noise every bin is near 0 dB.
  std::vector<float> take_db();

 private:
  std::size_t bins_;
  std::vector<float> window_;
  float window_power_ = 0.0F;
  std::vector<cf32> block_;
  std::size_t filled_ = 0;
  std::vector<cf32> scratch_;
  std::vector<double> sum_;
  std::size_t blocks_ = 0;
};

}  // namespace rfsitl::monitor
