#include "front_end.hpp"

#include <algorithm>
#include <numeric>

namespace rfsitl::phy::dsss::detail {

void FrontEnd::configure(unsigned samples_per_chip, std::size_t period, std::size_t energy_periods,
                         std::size_t y_history, std::size_t e_history, std::size_t max_block) {
  samples_per_chip_ = samples_per_chip;
  period_ = period;
  x_.configure(samples_per_chip, max_block);
  y_.configure(y_history, max_block);
  e_.configure(e_history, max_block);
  period_energy_.assign(energy_periods, 0.0F);
  reset();
}

void FrontEnd::reset() {
  x_.reset();
  y_.reset();
  e_.reset();
  std::fill(period_energy_.begin(), period_energy_.end(), 0.0F);
  ring_pos_ = 0;
  complete_ = 0.0F;
  partial_ = 0.0F;
  phase_ = 0;
  complete_count_ = 0;
}

void FrontEnd::ingest(std::span<const cf32> x) {
  const std::size_t n = x.size();
  const std::int64_t first = x_.end();
  std::copy(x.begin(), x.end(), x_.append(n));
  cf32* y = y_.append(n);
  if (samples_per_chip_ == 1) {
    std::copy(x.begin(), x.end(), y);
  } else {
    // S <= 8 terms per sample: summing them directly costs little and, unlike a
    // running sum, carries no error from one sample to the next.
    const cf32* xp = x_.at(first);
    const auto s = static_cast<std::ptrdiff_t>(samples_per_chip_);
    for (std::size_t j = 0; j < n; ++j) {
      const auto jj = static_cast<std::ptrdiff_t>(j);
      cf32 acc{};
      for (std::ptrdiff_t k = 0; k < s; ++k) acc += xp[jj - k];
      y[j] = acc;
    }
  }
  float* e = e_.append(n);
  for (std::size_t j = 0; j < n; ++j) {
    partial_ += std::norm(x[j]);
    ++phase_;
    const std::size_t covered = complete_count_ * period_ + phase_;
    e[j] = (partial_ + complete_) / static_cast<float>(covered);
    if (phase_ == period_) {
      period_energy_[ring_pos_] = partial_;
      ring_pos_ = (ring_pos_ + 1) % period_energy_.size();
      complete_ = std::accumulate(period_energy_.begin(), period_energy_.end(), 0.0F);
      complete_count_ = std::min(complete_count_ + 1, period_energy_.size());
      partial_ = 0.0F;
      phase_ = 0;
    }
  }
}

}  // namespace rfsitl::phy::dsss::detail
