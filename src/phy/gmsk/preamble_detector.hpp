#pragma once
/// Acquisition that is cheap on noise: delay-and-correlate on the periodic
/// preamble (the idea of Schmidl and Cox's OFDM timing metric).
///
/// The preamble repeats every D = 8 k samples, and a GMSK signal whose symbols
/// repeat is itself periodic up to a constant phase turn (here a multiple of
/// 2 pi, since an 8-symbol period has an even number of sign changes), so over
/// the preamble y[n] y*[n - D] has a constant phase whatever the carrier phase,
/// symbol timing or (small) frequency offset.
///
/// The samples are first summed in groups of g (about k / 2, a divisor of D):
/// a boxcar filter and decimation to about two values per symbol. This keeps
/// the signal (whose bandwidth is about the symbol rate) and drops most of the
/// noise at k > 2, so that the test below sees the same SNR, and works on the
/// same number of values per window, whatever k. Over a window of W = 4 D / g
/// group sums u,
///   R = sum u[m] u*[m - D/g],  Ea = sum |u[m]|^2,  Eb = sum |u[m - D/g]|^2
/// and the test is M = |R|^2 / (Ea Eb) >= threshold (M <= 1 by Cauchy-Schwarz).
///
/// On white noise the group sums are independent and M is Beta(1, W - 1):
/// P(M > t) = (1 - t)^(W - 1), and the threshold is set for 1e-8 false
/// detections per test (0.25 for k = 2, 4, 8, where W = 64). Random GMSK data
/// gives a similar M (the window spans 32 symbols, whatever k). A preamble at
/// per-value SNR s gives M ~ (s / (1 + s))^2: 0.44 at 3 dB, 0.25 at 0 dB.
///
/// Work per sample: adds into the group sums; per group, one complex product
/// and a squared magnitude added into per-block sums (blocks of D samples,
/// float sums restarted every block, so nothing drifts; four partial sums in
/// scan(), so that the additions do not wait on each other). The metric is
/// tested once per block from the last four block sums. Timing comes later
/// from the sync word, so block granularity is enough: the preamble (8
/// periods) holds a full window (5 periods with the delay) at three or more
/// block boundaries.
#include <array>
#include <cmath>
#include <cstddef>

#include "rfsitl/common/types.hpp"

namespace rfsitl::phy::gmsk {

class PreambleDetector {
 public:
  static constexpr unsigned kWindowBlocks = 4;

  /// Precondition: 1 <= samples_per_symbol.
  explicit PreambleDetector(unsigned samples_per_symbol);

  /// D, the preamble period in samples.
  unsigned period_samples() const { return group_ * block_; }
  /// g, the samples summed per group.
  unsigned group_samples() const { return group_; }
  float threshold() const { return threshold_; }

  /// Forgets all history; the next kWindowBlocks + 1 blocks only fill the window.
  void reset();

  /// Feeds sample y[n] and y[n - D]. Returns true when this sample ends a block
  /// and the window ending here passes the test.
  bool push(cf32 x, cf32 x_delayed) {
    gx_ += x;
    gd_ += x_delayed;
    if (++in_group_ < group_) return false;
    in_group_ = 0;
    // Plain float arithmetic: std::complex's operator* checks for NaN and inf.
    acc_re_ += gx_.real() * gd_.real() + gx_.imag() * gd_.imag();
    acc_im_ += gx_.imag() * gd_.real() - gx_.real() * gd_.imag();
    acc_e_ += gx_.real() * gx_.real() + gx_.imag() * gx_.imag();
    gx_ = gd_ = cf32{};
    if (++in_block_ < block_) return false;
    return end_block();
  }

  /// push() over x[0 .. n) with delayed[i] = y[n - D] for x[i], stopping after
  /// the first sample for which push() would return true. Returns the number
  /// of samples consumed and sets *detected. The fast path on noise.
  std::size_t scan(const cf32* x, const cf32* delayed, std::size_t n, bool* detected);

  /// Metric M of the last completed block's window (0 until the window is full).
  float last_metric() const { return last_metric_; }

 private:
  std::size_t scan_ungrouped(const cf32* x, const cf32* delayed, std::size_t n, bool* detected);
  bool end_block();

  unsigned group_;  // g
  unsigned block_;  // D / g group sums per block
  float threshold_;
  unsigned in_group_ = 0;
  cf32 gx_{};  // the current group's sums of y[n] and y[n - D]
  cf32 gd_{};
  unsigned in_block_ = 0;
  float acc_re_ = 0.0F;  // sums over the current block
  float acc_im_ = 0.0F;
  float acc_e_ = 0.0F;
  // Block sums of the last 5 blocks, in rings whose newest entry is at
  // newest_ (the b-th newest at newest_ + b, modulo 5): R over the last 4
  // blocks; energies over the last 5 (Eb is Ea one block earlier).
  std::array<cf32, kWindowBlocks + 1> block_r_{};
  std::array<float, kWindowBlocks + 1> block_e_{};
  unsigned newest_ = 0;
  unsigned blocks_seen_ = 0;
  float last_metric_ = 0.0F;
};

}  // namespace rfsitl::phy::gmsk
