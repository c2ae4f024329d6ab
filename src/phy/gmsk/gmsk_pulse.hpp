#pragma once
/// The GMSK pulses, written from the definitions of continuous-phase modulation.
///
/// GMSK is CPM with modulation index h = 1/2 whose frequency pulse g(t) is a
/// rectangle of one symbol T convolved with a Gaussian of bandwidth B:
///   g(t) = 1/(2T) [Q(a (t/T - 1/2)) - Q(a (t/T + 1/2))],  a = 2 pi BT / sqrt(ln 2),
/// so that the phase pulse q(t) = integral of g rises from 0 to 1/2. The
/// transmitted phase is phi(t) = 2 pi h sum_i a_i q(t - iT) = pi sum_i a_i q(t - iT)
/// for symbols a_i in {-1, +1}: each symbol turns the phase by +-pi/2 in total.
///
/// Here g is truncated to `span` symbols, shifted to start at t = 0 and scaled
/// so that the truncated q still ends exactly at 1/2 (the phase then advances by
/// exactly +-pi/2 per symbol, which keeps the phase trellis exact).
///
/// Laurent's decomposition writes a binary CPM signal as a sum of PAM signals;
/// for GMSK the first one, with pulse C0 and pseudo-symbols
/// A_n = exp(j pi/2 sum_{i<=n} a_i), holds almost all the energy (> 99% for
/// BT = 0.5). A filter matched to C0 followed by a decision on A_n is the
/// receiver's coherent detector.
#include <vector>

namespace rfsitl::phy::gmsk {

/// Untruncated GMSK phase pulse q(t) (t in symbols, centred on the symbol it
/// belongs to), from the closed form of the integral of g; q(-inf) = 0,
/// q(+inf) = 1/2. Precondition: bt > 0.
double gaussian_phase_pulse(double t_symbols, double bt);

/// Sampled pulses for one configuration.
struct GmskPulse {
  unsigned samples_per_symbol = 0;  ///< k
  unsigned span_symbols = 0;        ///< L: truncated length of the frequency pulse
  /// phase[j] = pi q(j / k) for j = 0 .. L k: the phase (radians) a +1 symbol has
  /// contributed j samples after its pulse began; phase.front() == 0 and
  /// phase.back() == pi / 2.
  std::vector<double> phase;
  /// Laurent's principal pulse C0(j / k), j = 1 .. (L + 1) k - 1 (C0 vanishes at
  /// both ends of its support [0, (L + 1) T]), scaled to unit energy.
  std::vector<float> c0;
};

/// Preconditions: k >= 1, 0 < bt, span >= 1.
GmskPulse make_gmsk_pulse(unsigned samples_per_symbol, double bandwidth_time, unsigned span);

/// A span L for a BT that keeps all of the Gaussian that matters: ceil(1 + 6
/// sigma) symbols, sigma = sqrt(ln 2) / (2 pi BT) the Gaussian's width in
/// symbols (3 symbols at BT = 0.5, 5 at 0.2); 1 for BT <= 0 (no filter).
unsigned gaussian_span_symbols(double bandwidth_time);

}  // namespace rfsitl::phy::gmsk
