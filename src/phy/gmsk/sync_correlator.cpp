#include "sync_correlator.hpp"

#include <algorithm>

#include "frame_format.hpp"

namespace rfsitl::phy::gmsk {

static_assert(kSyncSymbols == 32, "SyncCorrelator::kTaps must equal kSyncSymbols");
static_assert(kPreambleSymbols >= 32 && 32 % kPreamblePeriodSymbols == 0,
              "the 32 preamble symbols before the sync word start a period");

SyncCorrelator::SyncCorrelator(unsigned samples_per_symbol, const ReceiverKernels& kernels)
    : kernels_(&kernels),
      k_(samples_per_symbol),
      kept_((2 * kTaps - 1) * samples_per_symbol),
      first_(kept_),
      end_(kept_),
      // Room for four blocks between moves.
      re_(kept_ + 4 * kMaxBlock),
      im_(kept_ + 4 * kMaxBlock) {
  // conj(j^i) c_i: j^-i is 1, -j, -1, j for i mod 4 = 0, 1, 2, 3. The preamble
  // symbols before the sync word have indices i - 32, the same modulo 4.
  static constexpr float kRe[4] = {1.0F, 0.0F, -1.0F, 0.0F};
  static constexpr float kIm[4] = {0.0F, -1.0F, 0.0F, 1.0F};
  for (std::size_t i = 0; i < kTaps; ++i) {
    const float c = static_cast<float>(sync_symbol(i));
    rr_[i] = kRe[i & 3U] * c;
    ri_[i] = kIm[i & 3U] * c;
    const float p = static_cast<float>(preamble_symbol(i % kPreamblePeriodSymbols));
    pre_rr_[i] = kRe[i & 3U] * p;
    pre_ri_[i] = kIm[i & 3U] * p;
  }
}

void SyncCorrelator::reset() {
  std::fill_n(re_.begin(), kept_, 0.0F);
  std::fill_n(im_.begin(), kept_, 0.0F);
  first_ = end_ = kept_;
}

void SyncCorrelator::push(std::span<const cf32> mf) {
  const std::size_t n = mf.size();
  if (end_ + n > re_.size()) {
    std::copy(re_.begin() + static_cast<std::ptrdiff_t>(end_ - kept_),
              re_.begin() + static_cast<std::ptrdiff_t>(end_), re_.begin());
    std::copy(im_.begin() + static_cast<std::ptrdiff_t>(end_ - kept_),
              im_.begin() + static_cast<std::ptrdiff_t>(end_), im_.begin());
    end_ = kept_;
  }
  first_ = end_;
  for (const cf32 v : mf) {
    re_[end_] = v.real();
    im_[end_] = v.imag();
    ++end_;
  }
  // The sync word's window of the value at index p starts at p - (S - 1) k.
  const std::size_t oldest = first_ - (kTaps - 1) * k_;
  kernels_->correlate(&re_[oldest], &im_[oldest], k_, rr_.data(), ri_.data(), n, c_re_.data(),
                      c_im_.data(), energy_.data());
}

cf32 SyncCorrelator::preamble_gain(std::size_t i) const {
  // The preamble's window ends one symbol before the sync word's begins.
  const std::size_t oldest = first_ + i - (2 * kTaps - 1) * k_;
  float c_re = 0.0F;
  float c_im = 0.0F;
  float energy = 0.0F;
  reference_kernels().correlate(&re_[oldest], &im_[oldest], k_, pre_rr_.data(), pre_ri_.data(), 1,
                                &c_re, &c_im, &energy);
  return cf32{c_re, c_im} / static_cast<float>(kTaps);
}

}  // namespace rfsitl::phy::gmsk
