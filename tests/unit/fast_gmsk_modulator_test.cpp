#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include "phy/gmsk/cpm_modulator.hpp"
#include "phy/gmsk/gmsk_pulse.hpp"

namespace rfsitl::phy::gmsk {
namespace {

constexpr double kPi = std::numbers::pi;

std::vector<std::int8_t> random_symbols(std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<std::int8_t> a(n);
  for (auto& s : a) s = (rng() & 1U) != 0 ? std::int8_t{1} : std::int8_t{-1};
  return a;
}

/// GMSK's modulator: h = 1/2, the finished symbols as quarter turns.
std::vector<cf32> modulate(const GmskPulse& p, const std::vector<std::int8_t>& a) {
  CpmModulator m(gaussian_cpm_pulse(p, 0.5), CpmArithmetic::kFloatQuarterTurns);
  const std::size_t len = m.start(a);
  std::vector<cf32> x(len);
  EXPECT_EQ(m.generate(x), len);
  EXPECT_EQ(m.samples_left(), 0U);
  return x;
}

/// Phase change from sample n - 1 to n, in (-pi, pi].
double step_phase(const std::vector<cf32>& x, std::size_t n) {
  return std::arg(std::complex<double>(x[n]) * std::conj(std::complex<double>(x[n - 1])));
}

TEST(FastGmskPulse, PhasePulseRisesFromZeroToOneHalfAndIsAntisymmetric) {
  for (const double bt : {0.3, 0.5, 1.0}) {
    EXPECT_NEAR(gaussian_phase_pulse(-10.0, bt), 0.0, 1e-12);
    EXPECT_NEAR(gaussian_phase_pulse(10.0, bt), 0.5, 1e-12);
    EXPECT_NEAR(gaussian_phase_pulse(0.0, bt), 0.25, 1e-12);
    for (const double t : {0.2, 0.7, 1.3}) {
      EXPECT_NEAR(gaussian_phase_pulse(t, bt) + gaussian_phase_pulse(-t, bt), 0.5, 1e-12);
      EXPECT_GT(gaussian_phase_pulse(t, bt), gaussian_phase_pulse(t - 0.1, bt));
    }
  }
  // Narrower filters spread each symbol's phase turn over more time.
  EXPECT_LT(gaussian_phase_pulse(0.5, 0.3), gaussian_phase_pulse(0.5, 0.5));
}

TEST(FastGmskPulse, SampledPulsesAreNormalisedAndSymmetric) {
  const GmskPulse p = make_gmsk_pulse(4, 0.5, 3);
  ASSERT_EQ(p.phase.size(), 13U);
  EXPECT_DOUBLE_EQ(p.phase.front(), 0.0);
  EXPECT_DOUBLE_EQ(p.phase.back(), kPi / 2.0);
  ASSERT_EQ(p.c0.size(), 15U);  // (L + 1) k - 1
  double energy = 0.0;
  for (std::size_t i = 0; i < p.c0.size(); ++i) {
    energy += p.c0[i] * p.c0[i];
    EXPECT_NEAR(p.c0[i], p.c0[p.c0.size() - 1 - i], 1e-6);
    EXPECT_GE(p.c0[i], 0.0F);
  }
  EXPECT_NEAR(energy, 1.0, 1e-5);
}

TEST(FastGmskPulse, SpanFollowsTheGaussianWidth) {
  EXPECT_EQ(gaussian_span_symbols(0.0), 1U);
  EXPECT_EQ(gaussian_span_symbols(1.0), 2U);
  EXPECT_EQ(gaussian_span_symbols(0.5), 3U);
  EXPECT_EQ(gaussian_span_symbols(0.3), 4U);
  EXPECT_EQ(gaussian_span_symbols(0.2), 5U);
}

TEST(FastGmskModulator, EnvelopeIsConstantUnitAmplitude) {
  for (const unsigned k : {2U, 4U, 8U}) {
    const auto x = modulate(make_gmsk_pulse(k, 0.5, 3), random_symbols(500, k));
    ASSERT_EQ(x.size(), (500U + 2U) * k);
    for (const cf32& v : x) ASSERT_NEAR(std::abs(v), 1.0F, 1e-5F);
  }
}

TEST(FastGmskModulator, PhaseTurnsByPlusOrMinusHalfPiPerSymbolAsMskDoes) {
  for (const unsigned k : {2U, 4U, 8U}) {
    const GmskPulse p = make_gmsk_pulse(k, 0.5, 3);
    // A run of equal symbols: once the pulses overlap fully, every symbol
    // period turns the phase by exactly +pi/2 (or -pi/2).
    for (const std::int8_t s : {std::int8_t{1}, std::int8_t{-1}}) {
      const auto x = modulate(p, std::vector<std::int8_t>(40, s));
      for (std::size_t n = 4 * k; n + k < 36 * k; n += k) {
        double turn = 0.0;
        for (std::size_t i = n + 1; i <= n + k; ++i) turn += step_phase(x, i);
        ASSERT_NEAR(turn, s * kPi / 2.0, 1e-5) << "k=" << k << " n=" << n;
      }
    }
    // Random symbols: the total turn is pi/2 times the symbol sum, and the mean
    // absolute turn per symbol is below pi/2 (the Gaussian filter smooths
    // reversals) but close to it.
    const auto a = random_symbols(2000, 3 + k);
    const auto x = modulate(p, a);
    double total = 0.0;
    double abs_per_symbol = 0.0;
    for (std::size_t s = 0; s + 1 < x.size() / k; ++s) {
      double turn = 0.0;
      for (std::size_t i = s * k + 1; i <= (s + 1) * k; ++i) turn += step_phase(x, i);
      abs_per_symbol += std::abs(turn);
    }
    for (std::size_t i = 1; i < x.size(); ++i) total += step_phase(x, i);
    int sum = 0;
    for (const auto v : a) sum += v;
    // The last sample is k - 1 samples short of the end of the last pulse.
    EXPECT_NEAR(total + std::arg(x[0]), sum * kPi / 2.0, 0.1);
    abs_per_symbol /= static_cast<double>(x.size() / k - 1);
    EXPECT_GT(abs_per_symbol, 0.75 * kPi / 2.0);
    EXPECT_LT(abs_per_symbol, kPi / 2.0);
  }
}

}  // namespace
}  // namespace rfsitl::phy::gmsk
