#include "rfsitl/channel/link_budget.hpp"

#include <cmath>
#include <utility>

namespace rfsitl::channel {

LinkBudget::LinkBudget(double fixed_gain_db, std::vector<std::unique_ptr<GainStage>> stages)
    : fixed_gain_db_(fixed_gain_db),
      // pow(10, 0) is exactly 1: at 0 dBm the paper's coefficients come out
      // bit for bit as its formula gives them.
      fixed_amplitude_(std::pow(10.0, fixed_gain_db / 20.0)),
      stages_(std::move(stages)) {
  for (const auto& s : stages_) reciprocal_ = reciprocal_ && s->reciprocal();
}

cf32 LinkBudget::coefficient(const LinkGeometry& link) const {
  std::complex<double> c = fixed_amplitude_;
  for (const auto& s : stages_) c *= s->gain(link);
  // Evaluated in double and rounded once.
  return {static_cast<float>(c.real()), static_cast<float>(c.imag())};
}

}  // namespace rfsitl::channel
