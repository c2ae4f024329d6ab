#include "rfsitl/monitor/spectrum.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace rfsitl::monitor {

void fft_in_place(std::span<cf32> x) {
  const std::size_t n = x.size();
  // Bit-reversal permutation, then log2(n) butterfly stages.
  for (std::size_t i = 1, j = 0; i < n; ++i) {
    std::size_t bit = n >> 1;
    for (; (j & bit) != 0; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) std::swap(x[i], x[j]);
  }
  for (std::size_t len = 2; len <= n; len <<= 1) {
    const double angle = -2.0 * std::numbers::pi / static_cast<double>(len);
    const std::complex<double> step(std::cos(angle), std::sin(angle));
    for (std::size_t i = 0; i < n; i += len) {
      std::complex<double> w(1.0, 0.0);
      for (std::size_t k = 0; k < len / 2; ++k) {
        const cf32 u = x[i + k];
        const cf32 v =
            x[i + k + len / 2] * cf32(static_cast<float>(w.real()), static_cast<float>(w.imag()));
        x[i + k] = u + v;
        x[i + k + len / 2] = u - v;
        w *= step;
      }
    }
  }
}

SpectrumAverager::SpectrumAverager(std::size_t bins)
    : bins_(bins), window_(bins), block_(bins), scratch_(bins), sum_(bins, 0.0) {
  for (std::size_t i = 0; i < bins; ++i) {
    const double w = 0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * static_cast<double>(i) /
                                          static_cast<double>(bins));
    window_[i] = static_cast<float>(w);
    window_power_ += window_[i] * window_[i];
  }
}

void SpectrumAverager::add(std::span<const cf32> samples) {
  while (!samples.empty()) {
    const std::size_t take = std::min(samples.size(), bins_ - filled_);
    std::copy_n(samples.begin(), take, block_.begin() + static_cast<std::ptrdiff_t>(filled_));
    filled_ += take;
    samples = samples.subspan(take);
    if (filled_ < bins_) return;
    filled_ = 0;
    for (std::size_t i = 0; i < bins_; ++i) scratch_[i] = block_[i] * window_[i];
    fft_in_place(scratch_);
    for (std::size_t k = 0; k < bins_; ++k) sum_[k] += std::norm(scratch_[k]);
    ++blocks_;
  }
}

std::vector<float> SpectrumAverager::take_db() {
  std::vector<float> out;
  if (blocks_ == 0) return out;
  out.resize(bins_);
  const double scale = 1.0 / (static_cast<double>(blocks_) * window_power_);
  for (std::size_t k = 0; k < bins_; ++k) {
    // fftshift: bin 0 (DC) goes to the middle.
    const double p = sum_[(k + bins_ / 2) % bins_] * scale;
    out[k] = static_cast<float>(10.0 * std::log10(std::max(p, 1e-30)));
  }
  std::fill(sum_.begin(), sum_.end(), 0.0);
  blocks_ = 0;
  return out;
}

}  // namespace rfsitl::monitor
