#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <random>
#include <vector>

#include "phy/dsss/code_correlator.hpp"
#include "phy/dsss/codes.hpp"
#include "phy/dsss/differential_psk.hpp"
#include "phy/dsss/spreader.hpp"

namespace rfsitl::phy::dsss {
namespace {

std::vector<cf32> random_qpsk(std::size_t n, std::uint32_t seed) {
  const cf32 points[4] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
  std::mt19937 rng(seed);
  std::vector<cf32> s(n);
  for (auto& v : s) v = points[rng() % 4];
  return s;
}

/// Chip-integrated samples, as the receiver's front end computes them, with
/// `pad` zeros in front so that the correlator can look back.
std::vector<cf32> chip_integrate(const std::vector<cf32>& x, unsigned sps, std::size_t pad) {
  std::vector<cf32> padded(pad, cf32{});
  padded.insert(padded.end(), x.begin(), x.end());
  std::vector<cf32> y(padded.size());
  for (std::size_t n = 0; n < padded.size(); ++n) {
    for (unsigned k = 0; k < sps && k <= n; ++k) y[n] += padded[n - k];
  }
  return y;
}

TEST(DsssSpreading, SpreadThenDespreadRecoversEverySymbol) {
  for (const char* name : {"barker11", "mseq31", "gold127:5"}) {
    for (const unsigned sps : {1U, 2U, 3U, 8U}) {
      const auto code = code_by_name(name).chips;
      const auto symbols = random_qpsk(40, 11);
      const auto x = spread(symbols, code, sps);
      const std::size_t period = code.size() * sps;
      ASSERT_EQ(x.size(), symbols.size() * period);
      const CodeCorrelator corr(code, sps);
      const std::size_t pad = corr.lookback();
      const auto y = chip_integrate(x, sps, pad);
      for (std::size_t k = 0; k < symbols.size(); ++k) {
        const cf32 z = corr.correlate(&y[pad + (k + 1) * period - 1]) / static_cast<float>(period);
        EXPECT_NEAR(std::abs(z - symbols[k]), 0.0F, 1e-5F) << name << " sps " << sps << " k " << k;
      }
    }
  }
}

TEST(DsssSpreading, FastPowerCorrelationMatchesTheDirectSum) {
  // The tiled kernel (vectorized, any length, not a multiple of the tile) must
  // agree with the textbook sum at every sample.
  const auto code = code_by_name("mseq63").chips;
  const unsigned sps = 2;
  std::mt19937 rng(5);
  std::normal_distribution<float> g(0.0F, 1.0F);
  std::vector<cf32> y(2000);
  for (auto& v : y) v = {g(rng), g(rng)};
  for (const auto kernel : {CodeCorrelator::Kernel::kBest, CodeCorrelator::Kernel::kPortable}) {
    const CodeCorrelator corr(code, sps, kernel);
    const std::size_t first = corr.lookback();
    const std::size_t count = y.size() - first;  // 1876: 117 tiles and a tail of 4
    std::vector<float> power(count);
    corr.correlate_power(&y[first], count, power.data());
    for (std::size_t j = 0; j < count; ++j) {
      cf32 z{};
      for (std::size_t i = 0; i < code.size(); ++i) {
        z += static_cast<float>(code[i]) * y[first + j - (code.size() - 1 - i) * sps];
      }
      ASSERT_NEAR(power[j], std::norm(z), 1e-3F * (1.0F + std::norm(z))) << "sample " << j;
    }
  }
}

TEST(DsssSpreading, OutputHasUnitPowerInEverySample) {
  const auto code = code_by_name("gold31:3").chips;
  const auto x = spread(random_qpsk(20, 3), code, 4);
  for (const cf32& v : x) ASSERT_NEAR(std::norm(v), 1.0F, 1e-6F);
}

TEST(DsssSpreading, SpreaderWritesInChunksExactlyWhatSpreadReturns) {
  const auto code = code_by_name("barker11").chips;
  const auto symbols = random_qpsk(9, 8);
  const auto whole = spread(symbols, code, 3);
  Spreader s;
  s.start(code, 3, symbols);
  std::vector<cf32> chunked;
  std::vector<cf32> buf(7);  // not a divisor of the chip, the period or the frame
  while (s.remaining() > 0) {
    const std::size_t n = s.write(buf);
    chunked.insert(chunked.end(), buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(n));
  }
  EXPECT_EQ(chunked, whole);
}

TEST(DsssSpreading, DifferentialDbpskRoundTrips) {
  DifferentialEncoder enc;
  std::vector<cf32> sym{cf32{1, 0}};  // reference
  const std::vector<std::uint8_t> bits = {0, 1, 1, 0, 1, 0, 0, 0, 1, 1};
  for (const auto b : bits) enc.push_bit(b, sym);
  for (std::size_t k = 0; k < bits.size(); ++k) {
    EXPECT_EQ(dbpsk_decide(sym[k + 1] * std::conj(sym[k])), bits[k]) << k;
  }
}

TEST(DsssSpreading, DqpskUsesThe80211bGrayMapping) {
  // 802.11b Table: d0 d1 = 00 -> 0, 01 -> +pi/2, 11 -> pi, 10 -> 3pi/2 (= -pi/2).
  struct Case {
    std::uint8_t d0, d1;
    cf32 rotation;
  };
  for (const Case c :
       {Case{0, 0, {1, 0}}, Case{0, 1, {0, 1}}, Case{1, 1, {-1, 0}}, Case{1, 0, {0, -1}}}) {
    DifferentialEncoder enc;
    std::vector<cf32> sym;
    enc.push_bit(0, sym);  // phase 0
    enc.push_dibit(c.d0, c.d1, sym);
    EXPECT_NEAR(std::abs(sym[1] * std::conj(sym[0]) - c.rotation), 0.0F, 1e-6F);
    // Decisions survive a common phase and a rotation error below 45 degrees.
    const cf32 d = sym[1] * std::conj(sym[0]) * std::polar(1.0F, 0.6F);
    EXPECT_EQ(dqpsk_decide(d), c.d0 | (c.d1 << 1));
  }
}

}  // namespace
}  // namespace rfsitl::phy::dsss
