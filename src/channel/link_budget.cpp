#include "rfsitl/channel/link_budget.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace rfsitl::channel {

LinkBudget::LinkBudget(double fixed_gain_db, std::vector<std::unique_ptr<GainStage>> stages)
    : fixed_gain_db_(fixed_gain_db),
      // pow(10, 0) is exactly 1: at 0 dBm the paper's coefficients come out
      // bit for bit as its formula gives them.
      fixed_amplitude_(std::pow(10.0, fixed_gain_db / 20.0)) {
  // Gains commute, so splitting the chain by kind changes no product.
  for (auto& s : stages) {
    if (s->time_varying()) {
      const double dt = s->update_interval_s();
      update_interval_s_ = update_interval_s_ == 0.0 ? dt : std::min(update_interval_s_, dt);
      fading_.push_back(std::move(s));
    } else {
      reciprocal_ = reciprocal_ && s->reciprocal();
      depends_on_attitude_ = depends_on_attitude_ || s->depends_on_attitude();
      if (s->dispersive()) dispersive_.push_back(s.get());
      large_scale_.push_back(std::move(s));
    }
  }
}

cf32 LinkBudget::coefficient(const LinkGeometry& link) const {
  std::complex<double> c = fixed_amplitude_;
  for (const auto& s : large_scale_) c *= s->gain(link);
  // Evaluated in double and rounded once.
  return {static_cast<float>(c.real()), static_cast<float>(c.imag())};
}

void LinkBudget::paths(const LinkGeometry& link, std::vector<Path>& out) const {
  std::complex<double> c = fixed_amplitude_;
  for (const auto& s : large_scale_) {
    if (!s->dispersive()) c *= s->gain(link);
  }
  out.assign(1, Path{0.0, c});
  std::vector<Path> stage;
  std::vector<Path> next;
  for (const GainStage* d : dispersive_) {
    stage.clear();
    d->paths(link, stage);
    next.clear();
    for (const Path& a : out) {
      for (const Path& b : stage) next.push_back({a.delay_s + b.delay_s, a.gain * b.gain});
    }
    out.swap(next);
  }
}

std::complex<double> LinkBudget::fading(const LinkGeometry& link) const {
  std::complex<double> h = 1.0;
  for (const auto& s : fading_) h *= s->gain(link);
  return h;
}

}  // namespace rfsitl::channel
