#pragma once
/// A power-of-two ring of recent input samples, addressed by absolute sample
/// time, so that filters can look back across receive() calls without copies.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

#include "rfsitl/common/types.hpp"

namespace rfsitl::phy::gmsk {

class SampleRing {
 public:
  /// Holds at least `min_size` samples (rounded up to a power of two).
  explicit SampleRing(std::size_t min_size)
      : buf_(std::bit_ceil(min_size)), mask_(buf_.size() - 1) {}

  std::size_t size() const { return buf_.size(); }
  void put(std::uint64_t t, cf32 x) { buf_[t & mask_] = x; }

  /// Writes x[0 .. n) as the samples of times t .. t + n - 1 (only the last
  /// size() of them stay).
  void put_block(std::uint64_t t, const cf32* x, std::size_t n) {
    if (n > buf_.size()) {
      x += n - buf_.size();
      t += n - buf_.size();
      n = buf_.size();
    }
    const std::size_t at = t & mask_;
    const std::size_t first = std::min(n, buf_.size() - at);
    std::copy_n(x, first, buf_.begin() + static_cast<std::ptrdiff_t>(at));
    std::copy_n(x + first, n - first, buf_.begin());
  }

  /// Precondition: t is one of the last size() times written.
  cf32 at(std::uint64_t t) const { return buf_[t & mask_]; }

  /// Copies the samples of times t .. t + n - 1 to out[0 .. n), contiguous.
  /// Precondition: n <= size() and they are among the last size() written.
  void copy_out(std::uint64_t t, std::size_t n, cf32* out) const {
    const std::size_t at = t & mask_;
    const std::size_t first = std::min(n, buf_.size() - at);
    std::copy_n(buf_.begin() + static_cast<std::ptrdiff_t>(at), first, out);
    std::copy_n(buf_.begin(), n - first, out + first);
  }

  /// sum_i taps[i] x[last - len + 1 + i]: a real filter whose window ends at
  /// time `last`. Precondition: len <= size() and the window was written.
  cf32 filter(std::uint64_t last, const float* taps, std::size_t len) const {
    const std::size_t start = (last + 1 - len) & mask_;
    float re = 0.0F;
    float im = 0.0F;
    if (start + len <= buf_.size()) {
      const cf32* x = buf_.data() + start;
      for (std::size_t i = 0; i < len; ++i) {
        re += taps[i] * x[i].real();
        im += taps[i] * x[i].imag();
      }
    } else {
      for (std::size_t i = 0; i < len; ++i) {
        const cf32 v = buf_[(start + i) & mask_];
        re += taps[i] * v.real();
        im += taps[i] * v.imag();
      }
    }
    return {re, im};
  }

  void clear() { std::fill(buf_.begin(), buf_.end(), cf32{}); }

 private:
  std::vector<cf32> buf_;
  std::uint64_t mask_;
};

}  // namespace rfsitl::phy::gmsk
