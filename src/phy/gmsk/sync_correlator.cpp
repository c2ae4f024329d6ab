#include "sync_correlator.hpp"

#include <algorithm>

#include "frame_format.hpp"

namespace rfsitl::phy::gmsk {

static_assert(kSyncSymbols == 32, "SyncCorrelator::kTaps must equal kSyncSymbols");
static_assert(kPreambleSymbols >= 32 && 32 % kPreamblePeriodSymbols == 0,
              "the 32 preamble symbols before the sync word start a period");

SyncCorrelator::SyncCorrelator(unsigned samples_per_symbol)
    : k_(samples_per_symbol),
      re_(2 * kHistory * samples_per_symbol),
      im_(2 * kHistory * samples_per_symbol),
      pos_(samples_per_symbol) {
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
  std::fill(re_.begin(), re_.end(), 0.0F);
  std::fill(im_.begin(), im_.end(), 0.0F);
  std::fill(pos_.begin(), pos_.end(), 0);
  phase_ = 0;
  last_x_ = last_y_ = nullptr;
  gain_ = {};
}

cf32 SyncCorrelator::correlate(const float* rr, const float* ri, const float* x, const float* y,
                               float* energy) {
  // (rr + j ri)(x + j y): real rr x - ri y, imaginary rr y + ri x. Eight
  // independent lanes per sum, so the additions need no reassociation and the
  // compiler can keep them in vector registers.
  constexpr std::size_t kLanes = 8;
  float cr[kLanes] = {};
  float ci[kLanes] = {};
  float en[kLanes] = {};
  for (std::size_t i = 0; i < kTaps; i += kLanes) {
    for (std::size_t l = 0; l < kLanes; ++l) {
      const float xv = x[i + l];
      const float yv = y[i + l];
      cr[l] += rr[i + l] * xv - ri[i + l] * yv;
      ci[l] += rr[i + l] * yv + ri[i + l] * xv;
      en[l] += xv * xv + yv * yv;
    }
  }
  float c_re = 0.0F;
  float c_im = 0.0F;
  float e = 0.0F;
  for (std::size_t l = 0; l < kLanes; ++l) {
    c_re += cr[l];
    c_im += ci[l];
    e += en[l];
  }
  *energy = e;
  return {c_re, c_im};
}

float SyncCorrelator::push(cf32 mf) {
  const std::size_t base = 2 * kHistory * phase_;
  const std::size_t w = pos_[phase_];
  re_[base + w] = re_[base + w + kHistory] = mf.real();
  im_[base + w] = im_[base + w + kHistory] = mf.imag();
  pos_[phase_] = w + 1 == kHistory ? 0 : w + 1;
  phase_ = phase_ + 1 == k_ ? 0 : phase_ + 1;

  // The last kHistory values oldest first; the sync word's window is the newer
  // half (x[S - 1] is `mf`).
  last_x_ = &re_[base + w + 1];
  last_y_ = &im_[base + w + 1];
  float energy = 0.0F;
  const cf32 c = correlate(rr_.data(), ri_.data(), last_x_ + kTaps, last_y_ + kTaps, &energy);
  const float s = static_cast<float>(kTaps);
  gain_ = c / s;
  return energy > 0.0F ? std::norm(c) / (s * energy) : 0.0F;
}

cf32 SyncCorrelator::preamble_gain() const {
  if (last_x_ == nullptr) return {};
  float energy = 0.0F;
  return correlate(pre_rr_.data(), pre_ri_.data(), last_x_, last_y_, &energy) /
         static_cast<float>(kTaps);
}

}  // namespace rfsitl::phy::gmsk
