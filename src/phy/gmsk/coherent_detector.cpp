#include "coherent_detector.hpp"

#include <algorithm>
#include <cmath>

namespace rfsitl::phy::gmsk {

void CoherentDetector::start(cf32 gain, std::size_t first_index, float frequency) {
  const float g2 = std::norm(gain);
  if (g2 > 0.0F) {
    eq_re_ = gain.real() / g2;
    eq_im_ = -gain.imag() / g2;
  } else {
    eq_re_ = 1.0F;
    eq_im_ = 0.0F;
  }
  magnitude2_ = eq_re_ * eq_re_ + eq_im_ * eq_im_;
  frequency_ = frequency;
  quarter_ = static_cast<unsigned>(first_index & 3U);
  since_renormalised_ = 0;
}

void CoherentDetector::decide(std::span<const cf32> mf, cf32* soft, std::uint8_t* bits) {
  // The state in locals: the compiler keeps them in registers across symbols
  // (members could alias the outputs as far as it knows).
  float eq_re = eq_re_;
  float eq_im = eq_im_;
  float frequency = frequency_;
  unsigned quarter = quarter_;
  unsigned since_renormalised = since_renormalised_;
  for (std::size_t s = 0; s < mf.size(); ++s) {
    // Plain float arithmetic: std::complex's operator* checks for NaN and inf.
    const float a = mf[s].real();
    const float b = mf[s].imag();
    float zr = a * eq_re - b * eq_im;
    float zi = a * eq_im + b * eq_re;
    // Multiply by j^-s exactly.
    switch (quarter) {
      case 1: {
        const float t = zr;
        zr = zi;
        zi = -t;
        break;
      }
      case 2:
        zr = -zr;
        zi = -zi;
        break;
      case 3: {
        const float t = zr;
        zr = -zi;
        zi = t;
        break;
      }
      default:
        break;
    }
    quarter = (quarter + 1) & 3U;
    soft[s] = {zr, zi};
    // Im z times the decision is ~ the phase error in radians; clipped so that
    // a noise spike cannot throw the loop. Branch-free: the data bit is random.
    const float error = std::clamp(std::copysign(1.0F, zr) * zi, -1.0F, 1.0F);
    frequency += kFrequencyGain * error;
    const float turn = kPhaseGain * error + frequency;
    // Turn the equaliser by -turn: a rotation by cos ~ 1 - turn^2 / 2, sin ~
    // turn, whose magnitude is 1 + O(turn^4); restore |1 / G| now and then, to
    // first order (x (3 - x^2) / 2 ~ x / |x| near |x| = 1), off the per-symbol path.
    const float c = 1.0F - 0.5F * turn * turn;
    const float nr = eq_re * c + eq_im * turn;
    const float ni = eq_im * c - eq_re * turn;
    eq_re = nr;
    eq_im = ni;
    if (++since_renormalised == 32) {
      since_renormalised = 0;
      const float fix = 1.5F - 0.5F * (nr * nr + ni * ni) / magnitude2_;
      eq_re *= fix;
      eq_im *= fix;
    }
    bits[s] = std::signbit(zr) ? 1U : 0U;
  }
  eq_re_ = eq_re;
  eq_im_ = eq_im;
  frequency_ = frequency;
  quarter_ = quarter;
  since_renormalised_ = since_renormalised;
}

}  // namespace rfsitl::phy::gmsk
