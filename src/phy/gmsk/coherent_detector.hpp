#pragma once
/// Symbol-by-symbol coherent detection of GMSK's Laurent pseudo-symbols, with a
/// decision-directed second-order phase-locked loop.
///
/// Symbol s's matched-filter sample is r_s ~ G j^s c_s (see frame_format.hpp), so
/// z_s = r_s j^-s / G ~ c_s: the bit is the sign of Re z_s (the real axis of
/// every symbol, which makes this an MSK-type I/Q detector with one matched
/// filter). Im z_s d_s (d_s the decision) is the phase error, which turns the
/// equaliser 1/G by a proportional and an integral (frequency) term, so a slow
/// drift or a small carrier offset is followed through long frames. The loop
/// gains are low: the quadrature interference of the neighbouring symbols also
/// lands in Im z and must average out.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "rfsitl/common/types.hpp"

namespace rfsitl::phy::gmsk {

class CoherentDetector {
 public:
  /// Starts a frame: `gain` is G at the next symbol, `first_index` that
  /// symbol's index s counted from the first sync symbol (only s mod 4
  /// matters) and `frequency` the carrier offset in radians per symbol.
  void start(cf32 gain, std::size_t first_index, float frequency);

  /// Decides the next n symbols; mf(i) gives symbol i's matched-filter sample
  /// (called once per symbol, in order). Writes each bit (0 for pseudo-symbol
  /// +1, 1 for -1) to bits[i] and z_s to soft[i].
  ///
  /// The loop is one long dependency chain (each decision turns the
  /// equaliser of the next symbol), so it keeps the state in registers, and
  /// it takes the filter as a function so that the filter's work, which
  /// depends on nothing here, runs in the chain's shadow.
  template <class MatchedFilter>
  void decide(std::size_t n, MatchedFilter&& mf, cf32* soft, std::uint8_t* bits) {
    State s = state_;
    for (std::size_t i = 0; i < n; ++i) bits[i] = step(s, mf(i), soft[i]);
    state_ = s;
  }

 private:
  static constexpr float kPhaseGain = 0.02F;
  static constexpr float kFrequencyGain = 2e-4F;

  struct State {
    float eq_re = 1.0F;  // the equaliser 1 / G, turned by the loop
    float eq_im = 0.0F;
    float magnitude2 = 1.0F;  // |1 / G|^2, kept while the loop turns the phase
    float frequency = 0.0F;   // radians per symbol
    unsigned quarter = 0;     // s mod 4
    unsigned since_renormalised = 0;
  };

  /// One symbol: returns its bit and writes z_s to `soft`.
  static std::uint8_t step(State& s, cf32 mf, cf32& soft) {
    // Plain float arithmetic: std::complex's operator* checks for NaN and inf.
    const float a = mf.real();
    const float b = mf.imag();
    float zr = a * s.eq_re - b * s.eq_im;
    float zi = a * s.eq_im + b * s.eq_re;
    // Multiply by j^-s exactly.
    switch (s.quarter) {
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
    s.quarter = (s.quarter + 1) & 3U;
    soft = {zr, zi};
    // Im z times the decision is ~ the phase error in radians; clipped so that
    // a noise spike cannot throw the loop. Branch-free: the data bit is random.
    const float error = std::clamp(std::copysign(1.0F, zr) * zi, -1.0F, 1.0F);
    s.frequency += kFrequencyGain * error;
    const float turn = kPhaseGain * error + s.frequency;
    // Turn the equaliser by -turn: a rotation by cos ~ 1 - turn^2 / 2, sin ~
    // turn, whose magnitude is 1 + O(turn^4); restore |1 / G| now and then, to
    // first order (x (3 - x^2) / 2 ~ x / |x| near |x| = 1), off the per-symbol path.
    const float c = 1.0F - 0.5F * turn * turn;
    const float nr = s.eq_re * c + s.eq_im * turn;
    const float ni = s.eq_im * c - s.eq_re * turn;
    s.eq_re = nr;
    s.eq_im = ni;
    if (++s.since_renormalised == 32) {
      s.since_renormalised = 0;
      const float fix = 1.5F - 0.5F * (nr * nr + ni * ni) / s.magnitude2;
      s.eq_re *= fix;
      s.eq_im *= fix;
    }
    return std::signbit(zr) ? 1U : 0U;
  }

  State state_;
};

}  // namespace rfsitl::phy::gmsk
