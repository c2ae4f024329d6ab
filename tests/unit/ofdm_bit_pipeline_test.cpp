// Property tests of the 802.11 OFDM transmit pipeline (IEEE 802.11-2016 clause
// 17): invariants and small hand-derived cases. The published Annex I values
// are checked in ofdm_conformance_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>
#include <set>
#include <span>
#include <stdexcept>
#include <vector>

#include "phy/ofdm/bit_pipeline.hpp"
#include "phy/ofdm/rates.hpp"
#include "phy/ofdm/waveform.hpp"

namespace rfsitl::phy::ofdm {
namespace {

std::vector<std::uint8_t> random_bits(std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<std::uint8_t> bits(n);
  for (auto& b : bits) b = static_cast<std::uint8_t>(rng() & 1U);
  return bits;
}

std::vector<std::uint8_t> random_bytes(std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<std::uint8_t> bytes(n);
  for (auto& b : bytes) b = static_cast<std::uint8_t>(rng() & 0xFFU);
  return bytes;
}

/// The bits of `v`, most significant first, `n` of them.
std::vector<std::uint8_t> bits_of(unsigned v, unsigned n) {
  std::vector<std::uint8_t> bits(n);
  for (unsigned i = 0; i < n; ++i) bits[i] = static_cast<std::uint8_t>((v >> (n - 1 - i)) & 1U);
  return bits;
}

// ---- bit pipeline ---------------------------------------------------------

TEST(OfdmBitPipeline, BytesToBitsIsLsbFirstAndInvertible) {
  const std::vector<std::uint8_t> bytes = {0x01, 0x80, 0xA5};
  const std::vector<std::uint8_t> bits = bytes_to_bits(bytes);
  const std::vector<std::uint8_t> want = {1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
                                          0, 0, 0, 1, 1, 0, 1, 0, 0, 1, 0, 1};
  EXPECT_EQ(bits, want);
  EXPECT_EQ(bits_to_bytes(bits), bytes);
  const std::vector<std::uint8_t> many = random_bytes(257, 3);
  EXPECT_EQ(bits_to_bytes(bytes_to_bits(many)), many);
  EXPECT_THROW(bits_to_bytes(std::vector<std::uint8_t>(7, 0)), std::invalid_argument);
}

TEST(OfdmBitPipeline, ScrambleTwiceIsIdentityForAllSeeds) {
  const std::vector<std::uint8_t> data = random_bits(1000, 7);
  for (unsigned seed = 1; seed < 128; ++seed) {
    std::vector<std::uint8_t> x = data;
    scramble(x, static_cast<std::uint8_t>(seed));
    EXPECT_NE(x, data) << "seed " << seed;
    scramble(x, static_cast<std::uint8_t>(seed));
    EXPECT_EQ(x, data) << "seed " << seed;
  }
  std::vector<std::uint8_t> x = data;
  EXPECT_THROW(scramble(x, 0), std::invalid_argument);
}

TEST(OfdmBitPipeline, SeedFromServiceRecoversAllSeeds) {
  std::set<std::vector<std::uint8_t>> prefixes;
  for (unsigned seed = 1; seed < 128; ++seed) {
    std::vector<std::uint8_t> service(16, 0);
    scramble(service, static_cast<std::uint8_t>(seed));
    prefixes.insert({service.begin(), service.begin() + 7});
    EXPECT_EQ(seed_from_service(std::span(service).first(7)), seed);
  }
  EXPECT_EQ(prefixes.size(), 127U);  // 7 output bits determine the state
}

TEST(OfdmBitPipeline, ScramblerSeedBitOrderAndPeriod) {
  // Seed 0x01 is x1 = 1: the 1 reaches x4 after three shifts (Figure 17-7).
  std::vector<std::uint8_t> x(8, 0);
  scramble(x, 0x01);
  EXPECT_EQ(x, (std::vector<std::uint8_t>{0, 0, 0, 1, 0, 0, 1, 1}));
  // Seed 0x40 is x7 = 1: it is output at once.
  std::vector<std::uint8_t> y(3, 0);
  scramble(y, 0x40);
  EXPECT_EQ(y, (std::vector<std::uint8_t>{1, 0, 0}));
  // Maximal-length sequence: period 127, with 64 ones per period.
  std::vector<std::uint8_t> z(254, 0);
  scramble(z, 0x7F);
  EXPECT_TRUE(std::equal(z.begin(), z.begin() + 127, z.begin() + 127));
  EXPECT_EQ(std::count(z.begin(), z.begin() + 127, 1), 64);
  // 17.3.5.5: the all-ones state yields 00001110 11110010 11001001 ...
  const std::vector<std::uint8_t> head = {0, 0, 0, 0, 1, 1, 1, 0, 1, 1, 1, 1,
                                          0, 0, 1, 0, 1, 1, 0, 0, 1, 0, 0, 1};
  EXPECT_TRUE(std::equal(head.begin(), head.end(), z.begin()));
}

TEST(OfdmBitPipeline, ConvolutionalEncoderImpulseResponseIsGenerators) {
  // A single 1 followed by zeros: output A traces g0 = 133 (1011011), output B
  // traces g1 = 171 (1111001), delay 0 first.
  std::vector<std::uint8_t> impulse(7, 0);
  impulse[0] = 1;
  const std::vector<std::uint8_t> out = convolutional_encode(impulse);
  ASSERT_EQ(out.size(), 14U);
  const std::vector<std::uint8_t> g0 = {1, 0, 1, 1, 0, 1, 1};
  const std::vector<std::uint8_t> g1 = {1, 1, 1, 1, 0, 0, 1};
  for (std::size_t i = 0; i < 7; ++i) {
    EXPECT_EQ(out[2 * i], g0[i]) << i;
    EXPECT_EQ(out[2 * i + 1], g1[i]) << i;
  }
  // Linearity: enc(a ^ b) = enc(a) ^ enc(b) from the zero state.
  const std::vector<std::uint8_t> a = random_bits(200, 1);
  const std::vector<std::uint8_t> b = random_bits(200, 2);
  std::vector<std::uint8_t> ab(200);
  std::transform(a.begin(), a.end(), b.begin(), ab.begin(), std::bit_xor<std::uint8_t>());
  const std::vector<std::uint8_t> ea = convolutional_encode(a);
  const std::vector<std::uint8_t> eb = convolutional_encode(b);
  std::vector<std::uint8_t> eab(400);
  std::transform(ea.begin(), ea.end(), eb.begin(), eab.begin(), std::bit_xor<std::uint8_t>());
  EXPECT_EQ(convolutional_encode(ab), eab);
}

TEST(OfdmBitPipeline, PunctureLengthsForEveryRate) {
  for (const RateParams& r : all_rates()) {
    for (unsigned n_sym : {1U, 2U, 7U}) {
      const std::size_t n_bits = static_cast<std::size_t>(n_sym) * r.n_dbps;
      const std::vector<std::uint8_t> coded = convolutional_encode(random_bits(n_bits, n_sym));
      EXPECT_EQ(puncture(coded, r.coding).size(), static_cast<std::size_t>(n_sym) * r.n_cbps)
          << r.mbps << " Mb/s";
    }
  }
  const std::vector<std::uint8_t> twelve(12, 1);
  EXPECT_EQ(puncture(twelve, CodeRate::kHalf).size(), 12U);
  EXPECT_EQ(puncture(twelve, CodeRate::kTwoThirds).size(), 9U);      // 3 of 4
  EXPECT_EQ(puncture(twelve, CodeRate::kThreeQuarters).size(), 8U);  // 4 of 6
}

TEST(OfdmBitPipeline, PuncturePatternsMatchFigure17_9) {
  // Tag each coded bit with its index (values fit in a byte) to see which survive.
  std::vector<std::uint8_t> idx(12);
  std::iota(idx.begin(), idx.end(), std::uint8_t{0});
  // R = 3/4: A0 B0 A1 B2 of A0 B0 A1 B1 A2 B2 (B1 = 3, A2 = 4 stolen).
  EXPECT_EQ(puncture(idx, CodeRate::kThreeQuarters),
            (std::vector<std::uint8_t>{0, 1, 2, 5, 6, 7, 8, 11}));
  // R = 2/3: A0 B0 A1 of A0 B0 A1 B1 (B1 = 3 stolen).
  EXPECT_EQ(puncture(idx, CodeRate::kTwoThirds),
            (std::vector<std::uint8_t>{0, 1, 2, 4, 5, 6, 8, 9, 10}));
  EXPECT_EQ(puncture(idx, CodeRate::kHalf), idx);
}

TEST(OfdmBitPipeline, InterleaverIsPermutationForEveryModulation) {
  for (const RateParams& r : all_rates()) {
    const std::vector<unsigned> perm = interleaver_permutation(r.n_cbps, r.n_bpsc);
    ASSERT_EQ(perm.size(), r.n_cbps);
    std::vector<unsigned> sorted = perm;
    std::sort(sorted.begin(), sorted.end());
    std::vector<unsigned> iota(r.n_cbps);
    std::iota(iota.begin(), iota.end(), 0U);
    EXPECT_EQ(sorted, iota) << r.mbps << " Mb/s";
    // 17.3.5.7: adjacent coded bits go to non-adjacent subcarriers.
    for (unsigned k = 0; k + 1 < r.n_cbps; ++k) {
      const int d = static_cast<int>(perm[k + 1] / r.n_bpsc) - static_cast<int>(perm[k] / r.n_bpsc);
      EXPECT_GE(std::abs(d), 2) << r.mbps << " Mb/s, k=" << k;
    }
    // interleave() applies the permutation: out[perm[k]] = in[k].
    const std::vector<std::uint8_t> in = random_bits(r.n_cbps, r.mbps);
    const std::vector<std::uint8_t> out = interleave(in, r.n_bpsc);
    for (unsigned k = 0; k < r.n_cbps; ++k) EXPECT_EQ(out[perm[k]], in[k]);
  }
}

TEST(OfdmBitPipeline, MapPointMatchesTables17_7To17_11) {
  const auto expect_point = [](unsigned v, unsigned n_bpsc, float re, float im) {
    const cf32 p = map_point(bits_of(v, n_bpsc), n_bpsc);
    EXPECT_NEAR(p.real(), re, 1e-6) << "bits " << v << " / " << n_bpsc;
    EXPECT_NEAR(p.imag(), im, 1e-6) << "bits " << v << " / " << n_bpsc;
  };
  const float q = 1.0F / std::sqrt(2.0F);
  const float s16 = 1.0F / std::sqrt(10.0F);
  const float s64 = 1.0F / std::sqrt(42.0F);
  expect_point(0b0, 1, -1.0F, 0.0F);  // Table 17-7 (BPSK)
  expect_point(0b1, 1, 1.0F, 0.0F);
  expect_point(0b00, 2, -q, -q);  // Table 17-8 (QPSK)
  expect_point(0b10, 2, q, -q);
  expect_point(0b01, 2, -q, q);
  expect_point(0b0000, 4, -3 * s16, -3 * s16);  // Table 17-9 (16-QAM)
  expect_point(0b0111, 4, -1 * s16, 1 * s16);
  expect_point(0b0110, 4, -1 * s16, 3 * s16);
  expect_point(0b1101, 4, 1 * s16, -1 * s16);
  expect_point(0b1001, 4, 3 * s16, -1 * s16);
  expect_point(0b000000, 6, -7 * s64, -7 * s64);  // Table 17-10 (64-QAM) corners
  expect_point(0b100000, 6, 7 * s64, -7 * s64);
  expect_point(0b000100, 6, -7 * s64, 7 * s64);
  expect_point(0b100100, 6, 7 * s64, 7 * s64);
  expect_point(0b011010, 6, -3 * s64, -1 * s64);  // b0b1b2 = 011 -> -3, 010 -> -1
  expect_point(0b111101, 6, 3 * s64, 5 * s64);
  EXPECT_THROW(map_point(bits_of(0, 3), 3), std::invalid_argument);
}

TEST(OfdmBitPipeline, MapPointHasUnitPowerAndGrayNeighbours) {
  for (unsigned n_bpsc : {1U, 2U, 4U, 6U}) {
    const unsigned m = 1U << n_bpsc;
    double power = 0.0;
    std::vector<cf32> pts;
    for (unsigned v = 0; v < m; ++v) {
      pts.push_back(map_point(bits_of(v, n_bpsc), n_bpsc));
      power += std::norm(pts.back());
    }
    EXPECT_NEAR(power / m, 1.0, 1e-5) << n_bpsc;
    // Gray coding: the closest points differ in exactly one bit.
    float d_min = 1e9F;
    for (unsigned a = 0; a < m; ++a) {
      for (unsigned b = a + 1; b < m; ++b) d_min = std::min(d_min, std::abs(pts[a] - pts[b]));
    }
    for (unsigned a = 0; a < m; ++a) {
      for (unsigned b = a + 1; b < m; ++b) {
        if (std::abs(pts[a] - pts[b]) < d_min * 1.001F) {
          EXPECT_EQ(std::popcount(a ^ b), 1) << n_bpsc << ": " << a << " vs " << b;
        }
      }
    }
  }
}

// ---- waveform -------------------------------------------------------------

TEST(OfdmWaveform, SubcarrierTables) {
  const std::array<int, 48>& d = data_subcarriers();
  EXPECT_TRUE(std::is_sorted(d.begin(), d.end()));
  EXPECT_EQ(d.front(), -26);
  EXPECT_EQ(d.back(), 26);
  EXPECT_EQ(pilot_subcarriers(), (std::array<int, 4>{-21, -7, 7, 21}));
  for (int k : d) {
    EXPECT_NE(k, 0);
    EXPECT_EQ(std::count(pilot_subcarriers().begin(), pilot_subcarriers().end(), k), 0);
  }
  EXPECT_EQ(std::set<int>(d.begin(), d.end()).size(), 48U);
  for (int k = -32; k < 32; ++k) {
    const bool used = k != 0 && k >= -26 && k <= 26;
    EXPECT_EQ(long_training_value(k) != cf32{}, used) << k;
    EXPECT_EQ(short_training_value(k) != cf32{}, used && k % 4 == 0) << k;
  }
}

TEST(OfdmWaveform, PilotPolarityStartAndPeriod) {
  const std::vector<int> head = {1, 1, 1, 1, -1, -1, -1, 1};
  for (unsigned n = 0; n < head.size(); ++n) EXPECT_EQ(pilot_polarity(n), head[n]) << n;
  int sum = 0;
  for (unsigned n = 0; n < 127; ++n) {
    EXPECT_EQ(pilot_polarity(n + 127), pilot_polarity(n)) << n;
    EXPECT_EQ(std::abs(pilot_polarity(n)), 1);
    sum += pilot_polarity(n);
  }
  EXPECT_EQ(sum, -1);  // m-sequence: 64 ones (-1) and 63 zeros (+1) per period
}

TEST(OfdmWaveform, DataSymbolCountIsCeilOfBitsOverNdbps) {
  for (const RateParams& r : all_rates()) {
    for (unsigned len = 1; len < 4096; ++len) {
      const auto want =
          static_cast<unsigned>(std::ceil(static_cast<double>(16 + 8 * len + 6) / r.n_dbps));
      ASSERT_EQ(data_symbol_count(r, len), want) << r.mbps << " Mb/s, " << len << " octets";
    }
  }
  EXPECT_EQ(data_symbol_count(*rate_from_mbps(36), 100), 6U);  // Annex I
}

TEST(OfdmWaveform, SignalFieldLayoutAndParity) {
  for (const RateParams& r : all_rates()) {
    for (unsigned len : {1U, 100U, 1500U, 4095U}) {
      const std::vector<std::uint8_t> b = signal_field_bits(r, len);
      ASSERT_EQ(b.size(), 24U);
      unsigned rate = 0;
      unsigned length = 0;
      for (unsigned i = 0; i < 4; ++i) rate |= static_cast<unsigned>(b[i]) << i;
      for (unsigned i = 0; i < 12; ++i) length |= static_cast<unsigned>(b[5 + i]) << i;
      EXPECT_EQ(rate, r.rate_field);
      EXPECT_EQ(b[4], 0);
      EXPECT_EQ(length, len);
      EXPECT_EQ(std::accumulate(b.begin(), b.begin() + 18, 0U) % 2, 0U);  // even parity
      EXPECT_TRUE(std::all_of(b.begin() + 18, b.end(), [](std::uint8_t v) { return v == 0; }));
    }
  }
  EXPECT_THROW(signal_field_bits(*rate_from_mbps(6), 4096), std::invalid_argument);
}

TEST(OfdmWaveform, BuildPpduLengthForEveryRate) {
  for (const RateParams& r : all_rates()) {
    for (std::size_t len : {std::size_t{1}, std::size_t{100}, std::size_t{1000}}) {
      const std::vector<std::uint8_t> psdu = random_bytes(len, static_cast<std::uint32_t>(len));
      const unsigned n_sym = data_symbol_count(r, static_cast<unsigned>(len));
      const std::vector<cf32> plain = build_ppdu(psdu, r, 0x5D, false);
      const std::vector<cf32> win = build_ppdu(psdu, r, 0x5D, true);
      EXPECT_EQ(plain.size(), 320U + 80U * (1U + n_sym)) << r.mbps << " Mb/s, " << len;
      EXPECT_EQ(win.size(), plain.size() + 1) << r.mbps << " Mb/s, " << len;
      // The window changes only the first sample of each field and adds the tail.
      std::set<std::size_t> edges = {0, 160, 320};
      for (unsigned n = 0; n <= n_sym; ++n) edges.insert(320 + 80 * n);
      for (std::size_t i = 0; i < plain.size(); ++i) {
        if (edges.count(i) == 0) {
          ASSERT_EQ(win[i], plain[i]) << r.mbps << " Mb/s, sample " << i;
        }
      }
    }
  }
}

TEST(OfdmWaveform, BuildPpduRejectsBadArguments) {
  const RateParams r = *rate_from_mbps(6);
  const std::vector<std::uint8_t> one(1, 0);
  EXPECT_THROW(build_ppdu({}, r, 1, false), std::invalid_argument);
  EXPECT_THROW(build_ppdu(std::vector<std::uint8_t>(4096, 0), r, 1, false), std::invalid_argument);
  EXPECT_THROW(build_ppdu(one, r, 0, false), std::invalid_argument);
  EXPECT_THROW(build_ppdu(one, r, 128, false), std::invalid_argument);
}

}  // namespace
}  // namespace rfsitl::phy::ofdm
