#include "preamble_detector.hpp"

#include <algorithm>

#include "frame_format.hpp"

namespace rfsitl::phy::gmsk {
namespace {

/// Below this mean power per sample the input is taken as silence (exact zeros
/// give 0 / 0); the emulator scales its noise floor to 1, far above.
constexpr float kSilencePower = 1e-9F;

/// Threshold t with (1 - t)^(W - 1) = 1e-8: the false detection probability
/// per test on white noise.
float threshold_for(unsigned window_values) {
  const double w = static_cast<double>(window_values);
  return static_cast<float>(1.0 - std::exp(std::log(1e-8) / (w - 1.0)));
}

/// The largest divisor of the period 8 k that is at most k / 2 (at least 1).
unsigned group_for(unsigned k) {
  const unsigned period = static_cast<unsigned>(kPreamblePeriodSymbols) * k;
  unsigned g = std::max(1U, k / 2);
  while (period % g != 0) --g;
  return g;
}

}  // namespace

PreambleDetector::PreambleDetector(unsigned samples_per_symbol)
    : group_(group_for(samples_per_symbol)),
      block_(static_cast<unsigned>(kPreamblePeriodSymbols) * samples_per_symbol / group_),
      threshold_(threshold_for(kWindowBlocks * block_)) {}

void PreambleDetector::reset() {
  in_group_ = 0;
  gx_ = gd_ = cf32{};
  in_block_ = 0;
  acc_re_ = acc_im_ = acc_e_ = 0.0F;
  block_r_.fill(cf32{});
  block_e_.fill(0.0F);
  newest_ = 0;
  blocks_seen_ = 0;
  last_metric_ = 0.0F;
}

std::size_t PreambleDetector::scan(const cf32* x, const cf32* delayed, std::size_t n,
                                   bool* detected) {
  if (group_ == 1) return scan_ungrouped(x, delayed, n, detected);
  *detected = false;
  std::size_t i = 0;
  while (i < n) {
    const std::size_t whole = std::min<std::size_t>((n - i) / group_, block_ - in_block_);
    if (in_group_ != 0 || whole == 0) {
      // A group split across calls: one sample at a time.
      if (push(x[i], delayed[i])) {
        *detected = true;
        return i + 1;
      }
      ++i;
      continue;
    }
    // Whole groups, with local sums (see scan_ungrouped).
    float re = 0.0F;
    float im = 0.0F;
    float en = 0.0F;
    for (std::size_t q = 0; q < whole; ++q) {
      float ar = 0.0F;
      float ai = 0.0F;
      float br = 0.0F;
      float bi = 0.0F;
      for (std::size_t j = 0; j < group_; ++j) {
        ar += x[i + j].real();
        ai += x[i + j].imag();
        br += delayed[i + j].real();
        bi += delayed[i + j].imag();
      }
      re += ar * br + ai * bi;
      im += ai * br - ar * bi;
      en += ar * ar + ai * ai;
      i += group_;
    }
    acc_re_ += re;
    acc_im_ += im;
    acc_e_ += en;
    in_block_ += static_cast<unsigned>(whole);
    if (in_block_ == block_ && end_block()) {
      *detected = true;
      return i;
    }
  }
  return i;
}

std::size_t PreambleDetector::scan_ungrouped(const cf32* x, const cf32* delayed, std::size_t n,
                                             bool* detected) {
  constexpr std::size_t kLanes = 4;
  std::size_t i = 0;
  *detected = false;
  while (i < n) {
    const std::size_t m = std::min<std::size_t>(block_ - in_block_, n - i);
    // Local partial sums: the compiler keeps them in registers (the members
    // could alias the input as far as it knows).
    float re[kLanes] = {};
    float im[kLanes] = {};
    float en[kLanes] = {};
    std::size_t j = 0;
    for (; j + kLanes <= m; j += kLanes) {
      for (std::size_t l = 0; l < kLanes; ++l) {
        const cf32 a = x[i + j + l];
        const cf32 b = delayed[i + j + l];
        re[l] += a.real() * b.real() + a.imag() * b.imag();
        im[l] += a.imag() * b.real() - a.real() * b.imag();
        en[l] += a.real() * a.real() + a.imag() * a.imag();
      }
    }
    for (; j < m; ++j) {
      const cf32 a = x[i + j];
      const cf32 b = delayed[i + j];
      re[0] += a.real() * b.real() + a.imag() * b.imag();
      im[0] += a.imag() * b.real() - a.real() * b.imag();
      en[0] += a.real() * a.real() + a.imag() * a.imag();
    }
    acc_re_ += (re[0] + re[1]) + (re[2] + re[3]);
    acc_im_ += (im[0] + im[1]) + (im[2] + im[3]);
    acc_e_ += (en[0] + en[1]) + (en[2] + en[3]);
    i += m;
    in_block_ += static_cast<unsigned>(m);
    if (in_block_ == block_ && end_block()) {
      *detected = true;
      return i;
    }
  }
  return i;
}

bool PreambleDetector::end_block() {
  // The oldest entry makes room for the newest (no shifting: a copy of the
  // arrays stalls the loads that follow it).
  constexpr unsigned kRing = kWindowBlocks + 1;
  newest_ = newest_ == 0 ? kRing - 1 : newest_ - 1;
  block_r_[newest_] = {acc_re_, acc_im_};
  block_e_[newest_] = acc_e_;
  acc_re_ = acc_im_ = acc_e_ = 0.0F;
  in_block_ = 0;
  if (blocks_seen_ <= kWindowBlocks) {
    ++blocks_seen_;
    return false;
  }
  cf32 r{};
  float ea = 0.0F;
  for (unsigned b = 0; b < kWindowBlocks; ++b) {
    const unsigned at = newest_ + b < kRing ? newest_ + b : newest_ + b - kRing;
    r += block_r_[at];
    ea += block_e_[at];
  }
  const unsigned oldest = newest_ == 0 ? kRing - 1 : newest_ - 1;
  const float eb = ea - block_e_[newest_] + block_e_[oldest];
  // A group sum of g samples has g times the power of one sample (noise) or
  // up to g^2 times (signal): g is the safe floor factor.
  const float floor = kSilencePower * static_cast<float>(kWindowBlocks * block_ * group_);
  if (ea <= floor || eb <= floor) {
    last_metric_ = 0.0F;
    return false;
  }
  last_metric_ = std::norm(r) / (ea * eb);
  return last_metric_ >= threshold_;
}

}  // namespace rfsitl::phy::gmsk
