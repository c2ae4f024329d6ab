#pragma once
/// What the module does to the samples of one direction, pure and separate
/// so that unit tests check it without an emulator: the frequency offset of
/// where the application is tuned, and its gain.
#include <cmath>
#include <complex>
#include <numbers>
#include <span>

#include "rfsitl/common/types.hpp"

namespace rfsitl::soapy {

/// What the application set for one direction: where it is tuned relative to
/// the emulator's carrier, and its gain.
struct PathTuning {
  bool in_band = true;     ///< false: tuned outside [carrier - fs/2, carrier + fs/2): silence
  double offset_hz = 0.0;  ///< tuned frequency - carrier, |offset| < fs/2 when in_band
  double gain_db = 0.0;    ///< amplitude scale 10^(gain/20)
};

/// The amplitude factor of `t`: 10^(gain/20), or 0 when tuned out of band.
inline double amplitude_of(const PathTuning& t) {
  return t.in_band ? std::pow(10.0, t.gain_db / 20.0) : 0.0;
}

/// Multiplies s[i] by amplitude * exp(j 2 pi f (t0 + i)), f in cycles per
/// sample. The phase follows the absolute virtual time t0 + i, so that chunks
/// shifted separately join without a phase jump.
inline void shift_and_scale(std::span<cf32> s, SampleTime t0, double cycles_per_sample,
                            double amplitude) {
  if (cycles_per_sample == 0.0) {
    for (auto& x : s) x *= static_cast<float>(amplitude);
    return;
  }
  // The start phase from the absolute time (fmod keeps it small), then a
  // rotator: a chunk is at most a few ticks, far too short to drift.
  const double start = std::fmod(cycles_per_sample * static_cast<double>(t0), 1.0);
  std::complex<double> rot = std::polar(amplitude, 2.0 * std::numbers::pi * start);
  const std::complex<double> step = std::polar(1.0, 2.0 * std::numbers::pi * cycles_per_sample);
  for (auto& x : s) {
    x = cf32(std::complex<double>(x) * rot);
    rot *= step;
  }
}

}  // namespace rfsitl::soapy
