#include "code_searcher.hpp"

#include <algorithm>

namespace rfsitl::phy::dsss::detail {
namespace {

// Fixed-size tiles let GCC vectorize at -O2 (see code_correlator.cpp).
constexpr std::size_t kTile = 16;

// D / (m L S mean power) on noise is Gamma(m, 1) / m for m periods; these are
// its 1e-7 upper quantiles for m = 1..8. Just after a (re)start fewer than 8
// periods exist and the statistic's tail is heavier, so the threshold is
// raised by kWarmup[m] / kWarmup[8] (the configured threshold holds at m = 8).
constexpr float kWarmup[kCombPeriods + 1] = {0.0F,   16.12F, 9.560F, 7.223F, 5.997F,
                                             5.231F, 4.703F, 4.314F, 4.014F};

// Verification of the chosen code phase over kSettlePeriods periods:
// its despread power over its mean on noise (the "strength", ~1 + L S SINR)
// must reach the detection threshold again. A frame that decodes has ~6 (Barker)
// to ~9; another code of the same Gold family leaks at most 1 + S t(n)^2 / L
// (3.3 for gold127, 3.6 for gold31 at S = 1), so at one sample per chip such a
// leak is never taken for a preamble, however strong the frame that causes it.
constexpr float kConfirmThreshold = 4.0F;
// ...and the periods must add up coherently, as the constant preamble does:
// |sum z|^2 >= kCoherence * kSettlePeriods * sum |z|^2. A preamble at a despread
// SNR of 2 (3 dB, below what decodes) still gives ~0.72; data symbols pass only
// when all six happen to be equal (1 in 32 for DBPSK, 1 in 1024 for DQPSK), so
// most detections inside a frame's data end here, after a few periods, instead
// of in a fruitless SFD search.
constexpr float kCoherence = 0.6F;

}  // namespace

void CodeSearcher::configure(const std::vector<Chip>& chips, unsigned samples_per_chip,
                             std::size_t max_block, float threshold, std::int64_t start) {
  correlator_ = CodeCorrelator(chips, samples_per_chip);
  period_ = correlator_.period();
  threshold_ = threshold;
  power_.configure(kCombPeriods * period_, max_block, start);
  computed_end_ = start;
  start_ = start;
  quiet_until_ = start;
  position_ = start;
  settling_ = false;
}

void CodeSearcher::begin_block(std::int64_t first, std::size_t n) {
  std::fill_n(power_.append(n), n, 0.0F);
  computed_end_ = first;
}

void CodeSearcher::restart(std::int64_t from, std::int64_t quiet_until) {
  const std::int64_t lo =
      std::max(power_.begin(), from - static_cast<std::int64_t>(kCombPeriods * period_));
  const std::int64_t hi = power_.end();
  if (lo < hi) std::fill(power_.at(lo), power_.at(lo) + (hi - lo), 0.0F);
  computed_end_ = from;
  quiet_until_ = quiet_until;
  position_ = from;
  settling_ = false;
}

void CodeSearcher::compute(const FrontEnd& fe, std::int64_t from, std::int64_t to) {
  const std::int64_t start = std::max({from, computed_end_, quiet_until_});
  if (start >= to) return;
  correlator_.correlate_power(fe.y(start), static_cast<std::size_t>(to - start), power_.at(start));
  computed_end_ = to;
}

std::optional<std::int64_t> CodeSearcher::first_crossing(const FrontEnd& fe, std::int64_t from,
                                                         std::int64_t to) const {
  const auto lag = static_cast<std::int64_t>(period_);
  const float per_period = static_cast<float>(period_);
  // Warm-up: the first kCombPeriods periods after a start, sample by sample.
  const std::int64_t warm_end =
      std::min(to, start_ + static_cast<std::int64_t>(kCombPeriods) * lag);
  for (std::int64_t t = from; t < warm_end; ++t) {
    const auto m = static_cast<std::size_t>((t - start_) / lag + 1);
    const float k = threshold_ * kWarmup[m] / kWarmup[kCombPeriods];
    if (comb(t, m) > k * static_cast<float>(m) * per_period * *fe.mean_power(t)) return t;
  }
  from = std::max(from, warm_end);
  if (from >= to) return std::nullopt;

  const auto n = static_cast<std::size_t>(to - from);
  const float* p = power_.at(from);
  const float* e = fe.mean_power(from);
  const float k = threshold_ * static_cast<float>(kCombPeriods) * per_period;
  std::size_t j = 0;
  for (; j + kTile <= n; j += kTile) {
    float d[kTile] = {};
    for (std::size_t m = 0; m < kCombPeriods; ++m) {
      const float* s = p + j - m * period_;
      for (std::size_t i = 0; i < kTile; ++i) d[i] += s[i];
    }
    bool hit = false;
    for (std::size_t i = 0; i < kTile; ++i) hit |= d[i] > k * e[j + i];
    if (!hit) continue;
    for (std::size_t i = 0; i < kTile; ++i) {
      if (d[i] > k * e[j + i]) return from + static_cast<std::int64_t>(j + i);
    }
  }
  for (; j < n; ++j) {
    float d = 0.0F;
    for (std::size_t m = 0; m < kCombPeriods; ++m) d += *(p + j - m * period_);
    if (d > k * e[j]) return from + static_cast<std::int64_t>(j);
  }
  return std::nullopt;
}

float CodeSearcher::comb(std::int64_t t, std::size_t periods) const {
  const float* p = power_.at(t);
  float sum = 0.0F;
  for (std::size_t m = 0; m < periods; ++m) sum += *(p - m * period_);
  return sum;
}

std::optional<Candidate> CodeSearcher::advance(const FrontEnd& fe, std::int64_t to) {
  if (position_ >= to) return std::nullopt;
  compute(fe, position_, to);
  while (position_ < to) {
    if (!settling_) {
      const auto t = first_crossing(fe, position_, to);
      if (!t) {
        position_ = to;
        return std::nullopt;
      }
      settling_ = true;
      window_begin_ = *t + static_cast<std::int64_t>(kSettlePeriods * period_);
      window_end_ = window_begin_ + static_cast<std::int64_t>(period_);
      best_score_ = -1.0F;
      best_sample_ = window_begin_;
      position_ = *t + 1;
      continue;
    }
    // Score every code phase over one period, kSettlePeriods periods after the
    // detection: by then the comb holds nothing from before the preamble.
    const std::int64_t hi = std::min(to, window_end_);
    for (std::int64_t t = std::max(position_, window_begin_); t < hi; ++t) {
      const float score = comb(t, kSettlePeriods);
      if (score > best_score_) {
        best_score_ = score;
        best_sample_ = t;
      }
    }
    position_ = hi;
    if (position_ < window_end_) return std::nullopt;
    settling_ = false;
    if (auto c = verdict(fe)) return c;
  }
  return std::nullopt;
}

std::optional<Candidate> CodeSearcher::verdict(const FrontEnd& fe) {
  cf32 sum{};
  float power = 0.0F;
  cf32 reference{};
  for (std::size_t m = 0; m < kSettlePeriods; ++m) {
    const cf32 z =
        correlator_.correlate(fe.y(best_sample_ - static_cast<std::int64_t>(m * period_)));
    if (m == 0) reference = z;
    sum += z;
    power += std::norm(z);
  }
  const float noise = *fe.mean_power(best_sample_) * static_cast<float>(kSettlePeriods * period_);
  if (power <= kConfirmThreshold * noise) return std::nullopt;
  if (std::norm(sum) < kCoherence * static_cast<float>(kSettlePeriods) * power) return std::nullopt;
  return Candidate{window_end_, best_sample_, reference, power / noise};
}

}  // namespace rfsitl::phy::dsss::detail
