#include "sts_detector.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "avx2_clones.hpp"

namespace rfsitl::phy::ofdm {
namespace {

// The block loops are compiled for AVX2 and plain x86-64 (avx2_clones.hpp).

constexpr float kThreshold = 0.55F;
constexpr float kTh2 = kThreshold * kThreshold;
constexpr unsigned kPlateau = 24;

/// out[i] = sum of q[i .. i + 47] for i in [0, n), by pairwise doubling into
/// sums of 16 (scratch t, n + 47 long) and then three of those: six vector adds
/// per output, and every window sum is the same tree of the same 48 values
/// wherever the blocks happen to start (no running sum to drift).
RFSITL_AVX2_CLONES void window_sums48(const float* q, std::size_t n, float* t, float* out) {
  const std::size_t m = n + 47;
  for (std::size_t j = 0; j + 1 < m; ++j) t[j] = q[j] + q[j + 1];   // pairs
  for (std::size_t j = 0; j + 3 < m; ++j) t[j] = t[j] + t[j + 2];   // fours
  for (std::size_t j = 0; j + 7 < m; ++j) t[j] = t[j] + t[j + 4];   // eights
  for (std::size_t j = 0; j + 15 < m; ++j) t[j] = t[j] + t[j + 8];  // sixteens
  for (std::size_t i = 0; i < n; ++i) out[i] = (t[i] + t[i + 16]) + t[i + 32];
}

/// Products x[i - 16] x*[i] as (ar br + ai bi, ai br - ar bi) and powers
/// |x[i]|^2 of the n samples after the kLag in xf (interleaved re, im).
RFSITL_AVX2_CLONES void products(const float* xf, std::size_t n, float* qr, float* qi, float* qw) {
  constexpr std::size_t kLag = StsDetector::kLag;
  for (std::size_t i = 0; i < n; ++i) {
    const float ar = xf[2 * i];
    const float ai = xf[2 * i + 1];
    const float br = xf[2 * (i + kLag)];
    const float bi = xf[2 * (i + kLag) + 1];
    qr[i] = ar * br + ai * bi;
    qi[i] = ai * br - ar * bi;
    qw[i] = br * br + bi * bi;
  }
}

/// The test |S| > 0.55 W as (|S| / W)^2 > 0.3025: no square of a strong
/// signal's sums to overflow a float. W = 0 (then S = 0) gives NaN: not above.
RFSITL_AVX2_CLONES void threshold(const float* sr, const float* si, const float* sw, std::size_t n,
                                  std::uint8_t* above) {
  for (std::size_t i = 0; i < n; ++i) {
    const float inv = 1.0F / sw[i];
    const float a = sr[i] * inv;
    const float b = si[i] * inv;
    above[i] = a * a + b * b > kTh2 ? 1 : 0;
  }
}

}  // namespace

void StsDetector::reset() {
  xs_.fill(cf32{});
  qr_.fill(0.0F);
  qi_.fill(0.0F);
  qw_.fill(0.0F);
  plateau_ = 0;
  filled_ = 0;
  detected_ = false;
  coarse_cfo_ = 0.0;
}

std::size_t StsDetector::search(std::span<const cf32> x) {
  std::size_t done = 0;
  while (done < x.size() && !detected_) {
    done += block(x.subspan(done, std::min<std::size_t>(kChunk, x.size() - done)));
  }
  return done;
}

std::size_t StsDetector::block(std::span<const cf32> x) {
  const std::size_t n = x.size();
  std::copy(x.begin(), x.end(), xs_.begin() + kLag);
  constexpr std::size_t kQ = kWindow - 1;
  products(reinterpret_cast<const float*>(xs_.data()), n, &qr_[kQ], &qi_[kQ], &qw_[kQ]);
  window_sums48(qr_.data(), n, scratch_.data(), sr_.data());
  window_sums48(qi_.data(), n, scratch_.data(), si_.data());
  window_sums48(qw_.data(), n, scratch_.data(), sw_.data());
  threshold(sr_.data(), si_.data(), sw_.data(), n, above_.data());

  // The first kWindow + kLag samples after reset() fill the delay line and the
  // window; they are not tested.
  std::size_t i = 0;
  const std::size_t warm = std::min<std::size_t>(n, kWindow + kLag - filled_);
  filled_ += static_cast<unsigned>(warm);
  i = warm;
  std::size_t used = n;
  for (; i < n; ++i) {
    plateau_ = above_[i] != 0 ? plateau_ + 1 : 0;
    if (plateau_ >= kPlateau) {
      detected_ = true;
      coarse_cfo_ = -std::atan2(static_cast<double>(si_[i]), static_cast<double>(sr_[i])) / kLag;
      used = i + 1;
      break;
    }
  }
  // Keep the history for the next block (after a detection the caller resets).
  std::copy(xs_.begin() + static_cast<std::ptrdiff_t>(n),
            xs_.begin() + static_cast<std::ptrdiff_t>(n + kLag), xs_.begin());
  std::copy_n(qr_.begin() + static_cast<std::ptrdiff_t>(n), kQ, qr_.begin());
  std::copy_n(qi_.begin() + static_cast<std::ptrdiff_t>(n), kQ, qi_.begin());
  std::copy_n(qw_.begin() + static_cast<std::ptrdiff_t>(n), kQ, qw_.begin());
  return used;
}

}  // namespace rfsitl::phy::ofdm
