#include "coherent_detector.hpp"

#include <algorithm>
#include <cmath>

namespace rfsitl::phy::gmsk {

void CoherentDetector::start(cf32 gain, std::size_t first_index, float frequency) {
  const float g2 = std::norm(gain);
  if (g2 > 0.0F) {
    state_.eq_re = gain.real() / g2;
    state_.eq_im = -gain.imag() / g2;
  } else {
    state_.eq_re = 1.0F;
    state_.eq_im = 0.0F;
  }
  state_.magnitude2 = state_.eq_re * state_.eq_re + state_.eq_im * state_.eq_im;
  state_.frequency = frequency;
  state_.quarter = static_cast<unsigned>(first_index & 3U);
  state_.since_renormalised = 0;
}

}  // namespace rfsitl::phy::gmsk
