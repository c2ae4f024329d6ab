#include "phy/ofdm/soft_decoding.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <random>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "phy/ofdm/bit_pipeline.hpp"
#include "phy/ofdm/rates.hpp"

namespace rfsitl::phy::ofdm {
namespace {

using Bits = std::vector<std::uint8_t>;

const std::string kVectors = RFSITL_SOURCE_DIR "/tests/vectors/ieee80211a-annex-i/";

Bits read_bits(const std::string& name) {
  std::ifstream in(kVectors + name);
  if (!in) throw std::runtime_error("cannot open " + kVectors + name);
  Bits bits;
  int b = 0;
  while (in >> b) bits.push_back(static_cast<std::uint8_t>(b));
  return bits;
}

std::vector<cf32> read_points(const std::string& name) {
  std::ifstream in(kVectors + name);
  if (!in) throw std::runtime_error("cannot open " + kVectors + name);
  std::vector<cf32> points;
  float re = 0.0F;
  float im = 0.0F;
  while (in >> re >> im) points.emplace_back(re, im);
  return points;
}

/// Hard bits as certain LLRs (bit 0 -> +1, bit 1 -> -1).
std::vector<float> strong_llrs(std::span<const std::uint8_t> bits) {
  std::vector<float> llr;
  for (std::uint8_t b : bits) llr.push_back(b != 0 ? -1.0F : 1.0F);
  return llr;
}

Bits random_bits(std::size_t n, std::mt19937& rng) {
  Bits bits(n);
  for (auto& b : bits) b = static_cast<std::uint8_t>(rng() & 1U);
  return bits;
}

std::size_t bit_errors(const Bits& a, const Bits& b) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) n += a[i] != b[i];
  return n + (a.size() > b.size() ? a.size() - b.size() : b.size() - a.size());
}

double db_to_linear(double db) {
  return std::pow(10.0, db / 10.0);
}

/// Transmit chain of one frame: encode, puncture, interleave and map per
/// symbol. `bits` must fill whole symbols.
std::vector<cf32> transmit(const Bits& bits, const RateParams& rate) {
  const Bits coded = puncture(convolutional_encode(bits), rate.coding);
  std::vector<cf32> points;
  for (std::size_t s = 0; s < coded.size(); s += rate.n_cbps) {
    const Bits sym = interleave(std::span(coded).subspan(s, rate.n_cbps), rate.n_bpsc);
    for (std::size_t k = 0; k < sym.size(); k += rate.n_bpsc) {
      points.push_back(map_point(std::span(sym).subspan(k, rate.n_bpsc), rate.n_bpsc));
    }
  }
  return points;
}

/// Adds complex AWGN of E|n|^2 = noise_var (unit-power constellations: SNR = 1 / noise_var).
void add_noise(std::vector<cf32>& points, float noise_var, std::mt19937& rng) {
  std::normal_distribution<float> n(0.0F, std::sqrt(noise_var / 2.0F));
  for (cf32& p : points) p += cf32{n(rng), n(rng)};
}

/// Receive chain up to the rate-1/2 LLR stream: demap, deinterleave, depuncture.
/// With `hard`, every LLR is cut to its sign (a hard-decision receiver).
std::vector<float> receive_llrs(const std::vector<cf32>& points, const RateParams& rate,
                                float noise_var, std::size_t n_bits, bool hard = false) {
  std::vector<float> llr;
  std::vector<float> sym(rate.n_cbps);
  const std::size_t per_symbol = rate.n_cbps / rate.n_bpsc;
  for (std::size_t s = 0; s < points.size(); s += per_symbol) {
    for (std::size_t k = 0; k < per_symbol; ++k) {
      demap_soft(points[s + k], rate.n_bpsc, noise_var,
                 std::span(sym).subspan(k * rate.n_bpsc, rate.n_bpsc));
    }
    const std::vector<float> d = deinterleave(sym, rate.n_bpsc);
    llr.insert(llr.end(), d.begin(), d.end());
  }
  if (hard) {
    for (float& v : llr) v = v > 0.0F ? 1.0F : (v < 0.0F ? -1.0F : 0.0F);
  }
  return depuncture(llr, rate.coding, n_bits);
}

TEST(OfdmSoftDecoding, ViterbiDecodesAnnexIDataFieldToScrambledBits) {
  // Table I-16 (R = 3/4 coded DATA field) back to Table I-15. The encoder is
  // not terminated at the end: 42 scrambled pad bits follow the zero tail.
  const Bits coded = read_bits("data_coded_bits.txt");
  const Bits expected = read_bits("data_scrambled_bits.txt");
  ASSERT_EQ(coded.size(), 1152U);
  ASSERT_EQ(expected.size(), 864U);
  const std::vector<float> half =
      depuncture(strong_llrs(coded), CodeRate::kThreeQuarters, expected.size());
  EXPECT_EQ(make_viterbi_decoder()->decode(half, expected.size(), false), expected);
}

TEST(OfdmSoftDecoding, ViterbiDecodesAnnexISignalFieldTerminated) {
  const Bits coded = read_bits("signal_coded_bits.txt");
  const Bits expected = read_bits("signal_bits.txt");
  ASSERT_EQ(coded.size(), 48U);
  const std::vector<float> half = depuncture(strong_llrs(coded), CodeRate::kHalf, 24);
  EXPECT_EQ(make_viterbi_decoder()->decode(half, 24, true), expected);
}

TEST(OfdmSoftDecoding, DeinterleaveRecoversAnnexICodedBits) {
  const auto check = [](const std::string& interleaved, const std::string& coded, unsigned n_bpsc) {
    const std::vector<float> out = deinterleave(strong_llrs(read_bits(interleaved)), n_bpsc);
    EXPECT_EQ(out, strong_llrs(read_bits(coded))) << interleaved;
  };
  check("data_sym1_interleaved_bits.txt", "data_sym1_coded_bits.txt", 4);  // Table I-19 -> I-16
  check("signal_interleaved_bits.txt", "signal_coded_bits.txt", 1);        // Table I-9 -> I-8
}

TEST(OfdmSoftDecoding, DemapAnnexIPointsGivesInterleavedBits) {
  const auto check = [](const std::string& points, const std::string& bits, unsigned n_bpsc) {
    const std::vector<cf32> p = read_points(points);
    const Bits expected = read_bits(bits);
    ASSERT_EQ(p.size() * n_bpsc, expected.size());
    Bits got;
    std::vector<float> llr(n_bpsc);
    for (cf32 x : p) {
      demap_soft(x, n_bpsc, 0.1F, llr);
      for (float v : llr) got.push_back(v < 0.0F ? 1 : 0);
    }
    EXPECT_EQ(got, expected) << points;
  };
  check("data_sym1_mapped_symbols.txt", "data_sym1_interleaved_bits.txt", 4);  // I-20 -> I-19
  check("signal_bpsk_symbols.txt", "signal_interleaved_bits.txt", 1);          // I-10 -> I-9
}

TEST(OfdmSoftDecoding, DemapMatchesStandardGrayTables) {
  // 17.3.5.8, per axis in units of 1/K_MOD: the labels of the levels -7 ... +7.
  const std::vector<std::vector<int>> qam16 = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
  const std::vector<std::vector<int>> qam64 = {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0},
                                               {1, 1, 0}, {1, 1, 1}, {1, 0, 1}, {1, 0, 0}};
  const auto check = [](const std::vector<std::vector<int>>& labels, float k_mod) {
    const auto m = static_cast<unsigned>(labels[0].size());
    const auto n = static_cast<int>(labels.size());
    for (int i = 0; i < n; ++i) {
      for (int q = 0; q < n; ++q) {
        const cf32 x{static_cast<float>(2 * i - n + 1) * k_mod,
                     static_cast<float>(2 * q - n + 1) * k_mod};
        std::vector<float> llr(2 * m);
        demap_soft(x, 2 * m, 0.01F, llr);
        for (unsigned j = 0; j < m; ++j) {
          EXPECT_EQ(llr[j] < 0.0F, labels[i][j] == 1) << "I level " << i << " bit " << j;
          EXPECT_EQ(llr[m + j] < 0.0F, labels[q][j] == 1) << "Q level " << q << " bit " << j;
        }
      }
    }
  };
  check(qam16, 1.0F / std::sqrt(10.0F));
  check(qam64, 1.0F / std::sqrt(42.0F));
}

TEST(OfdmSoftDecoding, DemapSignsMatchBitsForEveryConstellationPoint) {
  for (unsigned n_bpsc : {1U, 2U, 4U, 6U}) {
    for (unsigned v = 0; v < (1U << n_bpsc); ++v) {
      Bits bits(n_bpsc);
      for (unsigned j = 0; j < n_bpsc; ++j) bits[j] = static_cast<std::uint8_t>((v >> j) & 1U);
      std::vector<float> llr(n_bpsc);
      demap_soft(map_point(bits, n_bpsc), n_bpsc, 0.01F, llr);
      for (unsigned j = 0; j < n_bpsc; ++j) {
        EXPECT_EQ(llr[j] < 0.0F, bits[j] == 1) << "n_bpsc " << n_bpsc << " value " << v;
        EXPECT_GT(std::fabs(llr[j]), 1.0F);  // on a point: confident
      }
    }
  }
}

TEST(OfdmSoftDecoding, DemapBpskIsExactLogLikelihoodRatio) {
  // BPSK in complex AWGN of variance N0: llr = (|y - 1|^2 - |y + 1|^2) / N0 = -4 Re(y) / N0,
  // whatever Q holds.
  std::vector<float> llr(1);
  demap_soft({0.3F, 5.0F}, 1, 0.5F, llr);
  EXPECT_NEAR(llr[0], -4.0F * 0.3F / 0.5F, 1e-5F);
  EXPECT_THROW(demap_soft({0.0F, 0.0F}, 1, 0.0F, llr), std::invalid_argument);
  std::vector<float> three(3);
  EXPECT_THROW(demap_soft({0.0F, 0.0F}, 3, 1.0F, three), std::invalid_argument);
}

TEST(OfdmSoftDecoding, DeinterleaveInvertsInterleaveForAllModulations) {
  // One-hot inputs pin down every position; 64 / 2 is a non-standard size.
  const std::vector<std::pair<unsigned, unsigned>> sizes = {
      {48, 1}, {96, 2}, {192, 4}, {288, 6}, {64, 2}};
  for (const auto& [n_cbps, n_bpsc] : sizes) {
    for (unsigned k = 0; k < n_cbps; ++k) {
      Bits one_hot(n_cbps, 0);
      one_hot[k] = 1;
      const Bits tx = interleave(one_hot, n_bpsc);
      std::vector<float> soft(tx.begin(), tx.end());
      std::vector<float> expected(one_hot.begin(), one_hot.end());
      ASSERT_EQ(deinterleave(soft, n_bpsc), expected) << n_cbps << "/" << n_bpsc << " k " << k;
    }
  }
}

TEST(OfdmSoftDecoding, DepunctureRestoresPositionsWithErasuresForEveryRate) {
  struct Case {
    CodeRate rate;
    std::vector<int> stolen;  // positions within one period, from 17.3.5.6
    std::size_t period;
  };
  const std::vector<Case> cases = {{CodeRate::kHalf, {}, 2},
                                   {CodeRate::kTwoThirds, {3}, 4},          // B1
                                   {CodeRate::kThreeQuarters, {3, 4}, 6}};  // B1, A2
  std::mt19937 rng(7);
  for (const Case& c : cases) {
    const std::size_t n_data = 216;
    const Bits coded = random_bits(2 * n_data, rng);
    const std::vector<float> out = depuncture(strong_llrs(puncture(coded, c.rate)), c.rate, n_data);
    ASSERT_EQ(out.size(), coded.size());
    for (std::size_t i = 0; i < coded.size(); ++i) {
      const bool stolen = std::find(c.stolen.begin(), c.stolen.end(),
                                    static_cast<int>(i % c.period)) != c.stolen.end();
      EXPECT_EQ(out[i], stolen ? 0.0F : (coded[i] != 0 ? -1.0F : 1.0F)) << "position " << i;
    }
    EXPECT_THROW(depuncture(std::vector<float>(7), c.rate, n_data), std::invalid_argument);
  }
}

TEST(OfdmSoftDecoding, RoundTripRecoversRandomBitsAtEveryRate) {
  // Es/N0 a few dB above each rate's threshold: noisy, yet decodable without error.
  std::mt19937 rng(2024);
  for (const RateParams& rate : all_rates()) {
    const double snr_db = rate.n_bpsc == 1   ? 7.0
                          : rate.n_bpsc == 2 ? 10.0
                          : rate.n_bpsc == 4 ? 17.0
                                             : 24.0;
    const auto noise_var = static_cast<float>(1.0 / db_to_linear(snr_db));
    for (bool terminated : {true, false}) {
      const std::size_t n_bits = 20 * std::size_t{rate.n_dbps};
      Bits bits = random_bits(n_bits, rng);
      if (terminated) std::fill(bits.end() - 6, bits.end(), 0);
      std::vector<cf32> points = transmit(bits, rate);
      add_noise(points, noise_var, rng);
      const std::vector<float> llr = receive_llrs(points, rate, noise_var, n_bits);
      const Bits decoded = make_viterbi_decoder()->decode(llr, n_bits, terminated);
      EXPECT_EQ(bit_errors(decoded, bits), 0U)
          << rate.mbps << " Mb/s, " << (terminated ? "terminated" : "open");
    }
  }
}

TEST(OfdmSoftDecoding, ViterbiCorrectsAHandfulOfFlippedHardDecisions) {
  std::mt19937 rng(11);
  Bits bits = random_bits(600, rng);
  std::fill(bits.end() - 6, bits.end(), 0);
  const Bits coded = convolutional_encode(bits);
  std::vector<float> llr = strong_llrs(coded);
  // Five errors, far enough apart (free distance 10 corrects 4 per burst window).
  for (std::size_t pos : {13U, 200U, 201U, 640U, 1100U}) llr[pos] = -llr[pos];
  auto decoder = make_viterbi_decoder();
  EXPECT_EQ(decoder->decode(llr, bits.size(), true), bits);
  EXPECT_EQ(decoder->decode(llr, bits.size(), false), bits);
}

TEST(OfdmSoftDecoding, ViterbiTrustsTheZeroStartState) {
  // Any two paths from state 0 differ in >= 10 coded bits (the free distance), so
  // 3 errors anywhere are always corrected - also at the frame start, where a
  // decoder unsure of its start state would find closer paths from other states.
  std::mt19937 rng(3);
  const Bits bits = [&] {
    Bits b = random_bits(64, rng);
    std::fill(b.end() - 6, b.end(), 0);
    return b;
  }();
  const std::vector<float> clean = strong_llrs(convolutional_encode(bits));
  auto decoder = make_viterbi_decoder();
  for (std::size_t i = 0; i < 12; ++i) {
    for (std::size_t j = i + 1; j < 12; ++j) {
      for (std::size_t k = j + 1; k < 12; ++k) {
        std::vector<float> llr = clean;
        for (std::size_t pos : {i, j, k}) llr[pos] = -llr[pos];
        ASSERT_EQ(decoder->decode(llr, bits.size(), true), bits) << i << " " << j << " " << k;
      }
    }
  }
}

TEST(OfdmSoftDecoding, SoftDecisionsBeatHardDecisions) {
  // 16-QAM R = 1/2 at its threshold: the decoder that sees the reliabilities must
  // make strictly fewer bit errors than the one that sees signs only.
  const RateParams rate = *rate_from_mbps(24);
  const auto noise_var = static_cast<float>(1.0 / db_to_linear(8.0));
  std::mt19937 rng(99);
  auto decoder = make_viterbi_decoder();
  std::size_t soft_errors = 0;
  std::size_t hard_errors = 0;
  for (int frame = 0; frame < 20; ++frame) {
    const std::size_t n_bits = 10 * std::size_t{rate.n_dbps};
    Bits bits = random_bits(n_bits, rng);
    std::fill(bits.end() - 6, bits.end(), 0);
    std::vector<cf32> points = transmit(bits, rate);
    add_noise(points, noise_var, rng);
    soft_errors += bit_errors(
        decoder->decode(receive_llrs(points, rate, noise_var, n_bits), n_bits, true), bits);
    hard_errors += bit_errors(
        decoder->decode(receive_llrs(points, rate, noise_var, n_bits, true), n_bits, true), bits);
  }
  RecordProperty("soft_errors", std::to_string(soft_errors));
  RecordProperty("hard_errors", std::to_string(hard_errors));
  EXPECT_GT(hard_errors, 0U);
  EXPECT_LT(2 * soft_errors, hard_errors) << "soft " << soft_errors << ", hard " << hard_errors;
}

TEST(OfdmSoftDecoding, ViterbiReusedAcrossLengthsMatchesFreshDecoder) {
  // One decoder grows and shrinks its libfec instance between frames; each result
  // must equal that of a decoder that saw only this frame.
  std::mt19937 rng(5);
  auto reused = make_viterbi_decoder();
  for (std::size_t n : {48U, 12006U, 30U, 100U, 20000U, 7U}) {
    std::vector<float> llr(2 * n);
    std::normal_distribution<float> noise(0.0F, 1.0F);
    for (float& v : llr) v = noise(rng);  // pure noise: any state bug shows
    EXPECT_EQ(reused->decode(llr, n, false), make_viterbi_decoder()->decode(llr, n, false)) << n;
  }
}

TEST(OfdmSoftDecoding, ViterbiRejectsInconsistentSizes) {
  auto decoder = make_viterbi_decoder();
  EXPECT_THROW(decoder->decode(std::vector<float>(10), 6, true), std::invalid_argument);
  EXPECT_THROW(decoder->decode(std::vector<float>(8), 4, true), std::invalid_argument);
  EXPECT_TRUE(decoder->decode({}, 0, false).empty());
}

}  // namespace
}  // namespace rfsitl::phy::ofdm
