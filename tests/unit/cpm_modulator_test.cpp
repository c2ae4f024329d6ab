#include "phy/gmsk/cpm_modulator.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <complex>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

#include "phy/gfsk/gfsk_frame.hpp"
#include "phy/gfsk/gfsk_transceiver.hpp"
#include "phy/gmsk/fast_gmsk_transceiver.hpp"
#include "phy/gmsk/frame_format.hpp"
#include "phy/gmsk/gmsk_pulse.hpp"

namespace rfsitl::phy::gmsk {
namespace {

std::vector<std::int8_t> random_symbols(std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<std::int8_t> a(n);
  for (auto& s : a) s = (rng() & 1U) != 0 ? std::int8_t{1} : std::int8_t{-1};
  return a;
}

/// Gaussian pulse of `span` symbols at BT > 0, else the one-symbol rectangle.
CpmPulse pulse_for(unsigned k, double h, double bt, unsigned span) {
  return bt > 0.0 ? gaussian_cpm_pulse(make_gmsk_pulse(k, bt, span), h)
                  : rectangular_cpm_pulse(k, h);
}

std::vector<cf32> modulate(CpmModulator& m, const std::vector<std::int8_t>& a) {
  std::vector<cf32> x(m.start(a));
  EXPECT_EQ(m.generate(x), x.size());
  EXPECT_EQ(m.samples_left(), 0U);
  return x;
}

/// q(t), t in symbols from the pulse's start, straight from the definition: the
/// Gaussian phase pulse cut to [0, span] and scaled to end at 1/2, or t / 2
/// over one symbol for the rectangle (BT = 0).
double reference_q(double t, double bt, unsigned span) {
  if (t <= 0.0) return 0.0;
  if (t >= span) return 0.5;
  if (bt <= 0.0) return 0.5 * t;
  const double half = 0.5 * span;
  const double q0 = gaussian_phase_pulse(-half, bt);
  return 0.5 * (gaussian_phase_pulse(t - half, bt) - q0) / (gaussian_phase_pulse(half, bt) - q0);
}

/// x[n] = exp(j 2 pi h sum_i a_i q((n - i k) / k)) in double, from q itself:
/// no table and no reduction of the phase (symbols past their pulse add
/// a_i / 2 each, through a running sum).
std::vector<std::complex<double>> reference(unsigned k, double h, double bt, unsigned span,
                                            const std::vector<std::int8_t>& a) {
  std::vector<double> prefix(a.size() + 1, 0.0);  // prefix[m] = sum of a_i, i < m
  for (std::size_t i = 0; i < a.size(); ++i) prefix[i + 1] = prefix[i] + a[i];
  std::vector<std::complex<double>> x((a.size() + span - 1) * k);
  for (std::size_t n = 0; n < x.size(); ++n) {
    // Symbols i with n - i k >= span k have q = 1/2.
    const std::size_t first = n >= span * k ? std::min(a.size(), (n - span * k) / k + 1) : 0;
    double phi = std::numbers::pi * h * prefix[first];
    for (std::size_t i = first; i < a.size() && i * k <= n; ++i) {
      const double t = static_cast<double>(n - i * k) / k;
      phi += 2.0 * std::numbers::pi * h * a[i] * reference_q(t, bt, span);
    }
    x[n] = std::polar(1.0, phi);
  }
  return x;
}

struct Case {
  unsigned k;
  double h;
  double bt;
  unsigned span;
  CpmArithmetic arithmetic;
};

const Case kCases[] = {
    {2, 0.5, 0.5, 3, CpmArithmetic::kFloatQuarterTurns},  // GMSK's default
    {4, 0.5, 0.3, 4, CpmArithmetic::kFloatQuarterTurns},
    {8, 0.5, 1.0, 1, CpmArithmetic::kFloatQuarterTurns},
    {8, 2.0, 0.5, 3, CpmArithmetic::kDouble},  // GFSK's default (SiK)
    {5, 1.3, 0.2, 5, CpmArithmetic::kDouble},
    {4, 0.5, 0.5, 3, CpmArithmetic::kDouble},
    {8, 0.7, 0.0, 1, CpmArithmetic::kDouble},  // plain CPFSK
    {4, 1.0, 0.0, 1, CpmArithmetic::kDouble},
};

TEST(CpmModulator, BothArithmeticsFollowTheCpmDefinition) {
  for (const Case& c : kCases) {
    CpmModulator m(pulse_for(c.k, c.h, c.bt, c.span), c.arithmetic);
    ASSERT_EQ(m.span_symbols(), c.span);
    // Long enough that a drifting phase would show (thousands of pi h turns).
    const auto a = random_symbols(3000, c.k * 10 + c.span);
    const auto x = modulate(m, a);
    const auto want = reference(c.k, c.h, c.bt, c.span, a);
    ASSERT_EQ(x.size(), want.size());
    double worst = 0.0;
    for (std::size_t n = 0; n < x.size(); ++n) {
      worst = std::max(worst, std::abs(std::complex<double>(x[n]) - want[n]));
    }
    EXPECT_LT(worst, 1e-5) << "k=" << c.k << " h=" << c.h << " bt=" << c.bt;
  }
}

TEST(CpmModulator, RunsOfEqualSymbolsHaveTheToneOfTheDeviation) {
  // Deep inside a run the frequency is +-fd = +-h / (2k) cycles per sample (to
  // 0.05% at BT = 0.2, where the truncated pulse is renormalised); the
  // envelope is 1 throughout.
  for (const double bt : {0.0, 0.5, 0.2}) {
    const unsigned k = 8;
    const double h = 0.7;
    const unsigned span = gaussian_span_symbols(bt);
    CpmModulator m(pulse_for(k, h, bt, span), CpmArithmetic::kDouble);
    std::vector<std::int8_t> a(40, 1);
    std::fill(a.begin() + 20, a.end(), std::int8_t{-1});
    const auto x = modulate(m, a);
    for (const cf32& v : x) EXPECT_NEAR(std::abs(v), 1.0F, 1e-5F);
    const double fd = 2.0 * std::numbers::pi * h / (2.0 * k);
    for (std::size_t n = 10 * k; n < 14 * k; ++n) {
      EXPECT_NEAR(std::arg(x[n + 1] * std::conj(x[n])), fd, 1e-3) << "bt=" << bt << " n=" << n;
    }
    for (std::size_t n = 30 * k; n < 34 * k; ++n) {
      EXPECT_NEAR(std::arg(x[n + 1] * std::conj(x[n])), -fd, 1e-3) << "bt=" << bt << " n=" << n;
    }
  }
}

TEST(CpmModulator, QuarterTurnsRefuseAnIndexOtherThanOneHalf) {
  EXPECT_THROW(CpmModulator(rectangular_cpm_pulse(4, 1.0), CpmArithmetic::kFloatQuarterTurns),
               std::invalid_argument);
}

TEST(CpmModulator, GeneratesInAnyChunkSizeTheSameSamples) {
  for (const Case& c : kCases) {
    const auto a = random_symbols(301, 4);
    CpmModulator whole_m(pulse_for(c.k, c.h, c.bt, c.span), c.arithmetic);
    const auto whole = modulate(whole_m, a);
    CpmModulator m(pulse_for(c.k, c.h, c.bt, c.span), c.arithmetic);
    m.start(a);
    std::vector<cf32> chunked;
    std::vector<cf32> buf(37, cf32{9.0F, 9.0F});
    while (m.samples_left() > 0) {
      const std::size_t n = m.generate(buf);
      chunked.insert(chunked.end(), buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(n));
    }
    EXPECT_EQ(chunked, whole);
  }
}

TEST(CpmModulator, TransmitFillsWhatFollowsTheFrameWithZeros) {
  CpmModulator m(pulse_for(2, 0.5, 0.5, 3), CpmArithmetic::kFloatQuarterTurns);
  const std::vector<std::int8_t> a{1, -1, 1};
  ASSERT_EQ(m.start(a), 10U);
  std::vector<cf32> out(16, cf32{9.0F, 9.0F});
  EXPECT_EQ(m.transmit(out), 10U);
  for (std::size_t n = 0; n < 10; ++n) EXPECT_NEAR(std::abs(out[n]), 1.0F, 1e-6F);
  for (std::size_t n = 10; n < 16; ++n) EXPECT_EQ(out[n], cf32{});
  EXPECT_EQ(m.transmit(out), 0U);
  EXPECT_EQ(out[0], cf32{});
}

/// Everything `t` sends for one frame, in chunks of `chunk` samples.
std::vector<cf32> transmit_all(Transceiver& t, std::size_t chunk) {
  std::vector<cf32> all;
  std::vector<cf32> buf(chunk);
  while (t.tx_busy()) {
    const std::size_t n = t.transmit(buf);
    all.insert(all.end(), buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(n));
  }
  return all;
}

bool same_bits(const std::vector<cf32>& a, const std::vector<cf32>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(cf32)) == 0;
}

TEST(CpmModulator, GmskTransceiverSendsTheQuarterTurnModulatorsSamplesToTheBit) {
  const FrameTag tag{4, 7, 0x01020304U};
  const std::vector<std::uint8_t> payload{0x00, 0x5A, 0xFF, 0x13, 0x80};
  for (const unsigned k : {2U, 4U}) {
    const FastGmskSettings s{k, 0.3F, 4, 64};
    auto t = make_fast_gmsk_transceiver(s);
    const std::size_t total = t->start_frame(tag, payload);
    const auto sent = transmit_all(*t, 250);
    std::vector<std::int8_t> symbols(frame_symbol_count(payload.size()));
    build_frame_symbols(tag, payload, symbols);
    CpmModulator m(gaussian_cpm_pulse(make_gmsk_pulse(k, s.bandwidth_time, 4), 0.5),
                   CpmArithmetic::kFloatQuarterTurns);
    const auto want = modulate(m, symbols);
    ASSERT_EQ(want.size(), total);
    EXPECT_TRUE(same_bits(sent, want)) << "k=" << k;
  }
}

TEST(CpmModulator, GfskTransceiverSendsTheDoubleModulatorsSamplesToTheBit) {
  const FrameTag tag{2, 9, 77};
  const std::vector<std::uint8_t> payload{0xDE, 0xAD, 0xBE, 0xEF, 0x42, 0x00};
  GfskSettings shaped;  // SiK: k = 8, h = 2, BT = 0.5
  GfskSettings plain;
  plain.samples_per_symbol = 4;
  plain.modulation_index = 1.0F;
  plain.bandwidth_time = 0.0F;
  for (const GfskSettings& s : {shaped, plain}) {
    auto t = make_gfsk_transceiver(s);
    const std::size_t total = t->start_frame(tag, payload);
    const auto sent = transmit_all(*t, 99);
    std::vector<std::int8_t> symbols(gfsk::frame_bits(s.preamble_bytes, payload.size()));
    gfsk::build_frame_symbols(s.preamble_bytes, s.whitening, tag, payload, symbols);
    const unsigned span = gaussian_span_symbols(s.bandwidth_time);
    CpmModulator m(pulse_for(s.samples_per_symbol, s.modulation_index, s.bandwidth_time, span),
                   CpmArithmetic::kDouble);
    const auto want = modulate(m, symbols);
    ASSERT_EQ(want.size(), total);
    EXPECT_TRUE(same_bits(sent, want)) << "bt=" << s.bandwidth_time;
  }
}

}  // namespace
}  // namespace rfsitl::phy::gmsk
