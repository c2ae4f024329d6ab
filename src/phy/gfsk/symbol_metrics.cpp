#include "symbol_metrics.hpp"

#include <algorithm>
#include <complex>

namespace rfsitl::phy::gfsk {

EnergyMetric::EnergyMetric(unsigned k, float h)
    : k_(k),
      omega_(std::numbers::pi * h / k),
      rot_(std::polar(1.0F, static_cast<float>(omega_))),
      up_(k),
      down_(k) {}

void EnergyMetric::reset() {
  std::fill(up_.begin(), up_.end(), cf32{});
  std::fill(down_.begin(), down_.end(), cf32{});
  sum_up_ = sum_down_ = cf32{};
  osc_ = cf32{1.0F, 0.0F};
  slot_ = 0;
  since_resync_ = 0;
  t_ = 0;
}

void EnergyMetric::resync() {
  since_resync_ = 0;
  sum_up_ = sum_down_ = cf32{};
  for (unsigned i = 0; i < k_; ++i) {
    sum_up_ += up_[i];
    sum_down_ += down_[i];
  }
  // The oscillator afresh from its phase, w t modulo 2 pi in double.
  osc_ = std::polar(1.0F, static_cast<float>(
                              std::fmod(omega_ * static_cast<double>(t_), 2.0 * std::numbers::pi)));
}

unsigned DiscriminatorMetric::boxcar_length(unsigned k, float h) {
  return std::max(1U, static_cast<unsigned>(std::lround(static_cast<float>(k) / (h + 1.0F))));
}

DiscriminatorMetric::DiscriminatorMetric(unsigned k, float h)
    : k_(k), m_(boxcar_length(k, h)), box_(m_), d_(k) {}

void DiscriminatorMetric::reset() {
  std::fill(box_.begin(), box_.end(), cf32{});
  box_sum_ = prev_ = cf32{};
  box_slot_ = 0;
  std::fill(d_.begin(), d_.end(), 0.0F);
  sum_ = 0.0F;
  slot_ = 0;
  since_resync_ = 0;
}

void DiscriminatorMetric::resync() {
  since_resync_ = 0;
  box_sum_ = cf32{};
  for (const cf32& v : box_) box_sum_ += v;
  sum_ = 0.0F;
  for (const float v : d_) sum_ += v;
}

}  // namespace rfsitl::phy::gfsk
