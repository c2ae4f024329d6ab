#pragma once
/// Packet detection on the 802.11a/g short training field (L-STF), by delay and
/// correlate: M = |sum x[n-16] x*[n]| / sum |x[n]|^2 over a window of 48
/// samples is about 1 / sqrt(48) on noise and S / (S + N) on the 16-periodic
/// L-STF. A packet is declared when M stays above 0.55 for 24 consecutive
/// samples (about 0 dB SNR and up).
///
/// Single precision, a block at a time, in loops the compiler vectorizes: the
/// products and powers of a block, then every window sum as a fixed tree of
/// pairwise additions (not a running sum, whose float rounding would pile up
/// over a long stream and after strong bursts), then the threshold test.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "rfsitl/common/types.hpp"

namespace rfsitl::phy::ofdm {

class StsDetector {
 public:
  StsDetector() { reset(); }

  /// Runs the detector over `x`; returns how many samples it consumed: all of
  /// them, or up to and including the one that completed a detection (then
  /// detected() is true). Precondition: !detected() (reset() after a detection).
  std::size_t search(std::span<const cf32> x);

  bool detected() const { return detected_; }
  /// -arg(sum x[n-16] x*[n]) / 16 at the detection: the carrier offset in
  /// radians per sample, within +-pi/16. Meaningful once detected().
  double coarse_cfo() const { return coarse_cfo_; }

  /// Forgets every sample seen (the first 64 samples after it are never tested).
  void reset();

  static constexpr unsigned kLag = 16;
  static constexpr unsigned kWindow = 48;

 private:
  static constexpr unsigned kChunk = 512;  // samples per block: the work arrays stay in L1

  /// One block of at most kChunk samples; returns how many it consumed.
  std::size_t block(std::span<const cf32> x);

  // Inputs: the last kLag samples before the block, then the block.
  std::array<cf32, kLag + kChunk> xs_{};
  // Products x[n-16] x*[n] (re, im) and powers |x[n]|^2: the last kWindow - 1
  // of the samples before the block, then the block's.
  std::array<float, kWindow - 1 + kChunk> qr_{};
  std::array<float, kWindow - 1 + kChunk> qi_{};
  std::array<float, kWindow - 1 + kChunk> qw_{};
  // Window sums ending at each sample of the block.
  std::array<float, kChunk> sr_{};
  std::array<float, kChunk> si_{};
  std::array<float, kChunk> sw_{};
  std::array<float, kWindow - 1 + kChunk> scratch_{};
  std::array<std::uint8_t, kChunk> above_{};
  unsigned plateau_ = 0;
  unsigned filled_ = 0;  // samples seen since reset(), up to kWindow + kLag
  bool detected_ = false;
  double coarse_cfo_ = 0.0;
};

}  // namespace rfsitl::phy::ofdm
