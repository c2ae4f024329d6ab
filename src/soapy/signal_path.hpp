#pragma once
/// What the module does to the samples of one direction, pure and separate
/// so that unit tests check it without an emulator: the frequency offset of
/// where the application is tuned, and its gain.
#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <span>

#include "rfsitl/common/types.hpp"

namespace rfsitl::soapy {

/// A direction's gain control as SoapySDR shows it: the settings an
/// application may choose, the one a new device has, and the one at which
/// samples pass unchanged, in the emulator's native units (its receivers'
/// noise has unit power; a transmitter at full scale sends unit power).
struct GainControl {
  double min_db = 0.0;
  double max_db = 0.0;
  double default_db = 0.0;
  double unity_db = 0.0;

  /// `value` moved into [min_db, max_db]: a real SDR's driver (UHD's) clamps
  /// an out-of-range gain rather than refusing it. NaN stays NaN.
  double clamp(double value) const {
    return std::isnan(value) ? value : std::clamp(value, min_db, max_db);
  }
  /// The amplitude scale, in dB, of setting `value` (PathTuning::gain_db).
  double scale_db(double value) const { return value - unity_db; }
};

/// RX. Every stream format shares one digital full scale (CF32 1.0 = CS16
/// 32767 = CS8 127, as getNativeStreamFormat says), and the gain maps the
/// emulator's native units onto it like a real receiver's gain maps antenna
/// power onto its ADC: the top of the range, 96 dB, passes the samples
/// unchanged (CF32 in native units); the default, 30 dB, puts unit-power
/// noise 66 dB below full scale (16 LSB RMS of complex magnitude in CS16,
/// 11.6 per component), leaving 66 dB above the noise before a steady signal
/// clips; 0 dB is 96 dB below native, for links up to about that far above
/// the noise.
inline constexpr GainControl kRxGain{0.0, 96.0, 30.0, 96.0};
/// TX: full scale (CF32 1.0, CS16 32767, CS8 127) at 0 dB is the emulator's
/// unit transmit power; the gain only attenuates.
inline constexpr GainControl kTxGain{-60.0, 0.0, 0.0, 0.0};

/// What the application set for one direction: where it is tuned relative to
/// the emulator's carrier, and its gain.
struct PathTuning {
  bool in_band = true;     ///< false: tuned outside [carrier - fs/2, carrier + fs/2): silence
  double offset_hz = 0.0;  ///< tuned frequency - carrier, |offset| < fs/2 when in_band
  double gain_db = 0.0;    ///< amplitude scale 10^(gain/20): GainControl::scale_db()
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
