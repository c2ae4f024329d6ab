#include "rfsitl/channel/frequency_shift.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

namespace rfsitl::channel {
namespace {

/// exp(j 2 pi frac(c t)): the product in long double (64 mantissa bits)
/// keeps its fraction exact to ~1e-7 cycles at t = 1e12 samples (weeks at 1 Msps).
std::complex<double> phasor_at(double cycles_per_sample, std::uint64_t t) {
  const long double turns =
      static_cast<long double>(cycles_per_sample) * static_cast<long double>(t);
  const auto frac = static_cast<double>(turns - std::floor(turns));
  return std::polar(1.0, 2.0 * std::numbers::pi * frac);
}

constexpr std::size_t kAnchorEvery = 256;

}  // namespace

void shift_frequency(std::span<cf32> x, double cycles_per_sample, std::uint64_t first_sample) {
  if (cycles_per_sample == 0.0) return;
  const std::complex<double> step = phasor_at(cycles_per_sample, 1);
  for (std::size_t i0 = 0; i0 < x.size(); i0 += kAnchorEvery) {
    const std::complex<double> w0 = phasor_at(cycles_per_sample, first_sample + i0);
    double wr = w0.real();
    double wi = w0.imag();
    const std::size_t end = std::min(x.size(), i0 + kAnchorEvery);
    // The products written out: std::complex's operator* would add the C99
    // Annex G NaN fix-up call per sample.
    for (std::size_t i = i0; i < end; ++i) {
      const double xr = x[i].real();
      const double xi = x[i].imag();
      x[i] = cf32{static_cast<float>(xr * wr - xi * wi), static_cast<float>(xr * wi + xi * wr)};
      const double next_r = wr * step.real() - wi * step.imag();
      wi = wr * step.imag() + wi * step.real();
      wr = next_r;
    }
  }
}

}  // namespace rfsitl::channel
