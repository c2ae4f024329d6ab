// The receiver's synchronization in single precision: the L-STF detector
// declares packets at the same sample, with the same coarse offset, as the
// double-precision running-sum detector it replaced (written out below), for
// any way the stream is cut into blocks and after long strong bursts; the LTF
// search finds T1 where the packet puts it and the carrier offset it was given.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include "phy/ofdm/ltf_search.hpp"
#include "phy/ofdm/rates.hpp"
#include "phy/ofdm/sts_detector.hpp"
#include "phy/ofdm/waveform.hpp"

namespace rfsitl::phy::ofdm {
namespace {

struct Detection {
  std::size_t index;  // of the sample that completed the plateau
  double cfo;
};

/// The detector as it was: double precision, sums kept by add and subtract.
std::optional<Detection> reference_detect(const std::vector<cf32>& x) {
  std::array<cf32, 16> delay{};
  std::array<std::complex<double>, 48> prods{};
  std::array<double, 48> powers{};
  std::complex<double> sum_prod;
  double sum_pow = 0.0;
  unsigned plateau = 0;
  for (std::size_t n = 0; n < x.size(); ++n) {
    const std::complex<double> prod =
        std::complex<double>(delay[n % 16]) * std::conj(std::complex<double>(x[n]));
    delay[n % 16] = x[n];
    sum_prod += prod - prods[n % 48];
    const double pw = std::norm(std::complex<double>(x[n]));
    sum_pow += pw - powers[n % 48];
    prods[n % 48] = prod;
    powers[n % 48] = pw;
    if (n < 64) continue;
    const bool above = sum_pow > 0.0 && std::norm(sum_prod) > 0.55 * 0.55 * sum_pow * sum_pow;
    plateau = above ? plateau + 1 : 0;
    if (plateau >= 24) return Detection{n, -std::arg(sum_prod) / 16.0};
  }
  return std::nullopt;
}

std::optional<Detection> detect(const std::vector<cf32>& x, std::size_t block) {
  StsDetector d;
  std::size_t at = 0;
  while (at < x.size()) {
    const std::size_t n = std::min(block, x.size() - at);
    const std::size_t used = d.search(std::span(x).subspan(at, n));
    at += used;
    if (d.detected()) return Detection{at - 1, d.coarse_cfo()};
    EXPECT_EQ(used, n);
  }
  return std::nullopt;
}

std::vector<cf32> ppdu(std::uint8_t seed) {
  const std::vector<std::uint8_t> psdu(60, seed);
  return build_ppdu(psdu, *rate_from_mbps(24), seed, false);
}

/// `lead` samples of unit noise, then the PPDU at `snr_db` (its mean power over
/// the noise's) turned by `cfo` radians per sample, then noise again.
std::vector<cf32> stream(std::size_t lead, double snr_db, double cfo, std::mt19937& rng) {
  const std::vector<cf32> frame = ppdu(static_cast<std::uint8_t>(1 + rng() % 127));
  double power = 0.0;
  for (const cf32& s : frame) power += std::norm(s);
  power /= static_cast<double>(frame.size());
  std::normal_distribution<float> g(0.0F, std::sqrt(0.5F));
  std::vector<cf32> x(lead + frame.size() + 200);
  for (cf32& s : x) s = {g(rng), g(rng)};
  const auto amp = static_cast<float>(std::sqrt(std::pow(10.0, snr_db / 10.0) / power));
  for (std::size_t i = 0; i < frame.size(); ++i) {
    const double ph = cfo * static_cast<double>(i);
    x[lead + i] +=
        amp * frame[i] * cf32(static_cast<float>(std::cos(ph)), static_cast<float>(std::sin(ph)));
  }
  return x;
}

TEST(StsDetector, DetectsWhereTheDoublePrecisionDetectorDid) {
  std::mt19937 rng(18);
  std::uniform_real_distribution<double> cfo(-0.15, 0.15);
  int compared = 0;
  for (double snr : {0.0, 3.0, 6.0, 10.0, 20.0, 30.0, 60.0}) {
    for (int trial = 0; trial < 20; ++trial) {
      const std::vector<cf32> x = stream(100 + rng() % 900, snr, cfo(rng), rng);
      const std::optional<Detection> want = reference_detect(x);
      for (std::size_t block : {std::size_t{1}, std::size_t{7}, std::size_t{250}, x.size()}) {
        const std::optional<Detection> got = detect(x, block);
        ASSERT_EQ(got.has_value(), want.has_value()) << "snr " << snr << " block " << block;
        if (!want) continue;
        EXPECT_EQ(got->index, want->index) << "snr " << snr << " block " << block;
        EXPECT_NEAR(got->cfo, want->cfo, 1e-5) << "snr " << snr << " block " << block;
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 480);  // of 560: all from a few dB up, most at 0 dB
}

/// Every detection in `x`, each search starting afresh after the last one (as
/// the receiver does after a packet), by the reference or by StsDetector.
std::vector<std::size_t> all_detections(const std::vector<cf32>& x, bool reference) {
  std::vector<std::size_t> found;
  std::size_t from = 0;
  while (from < x.size()) {
    const std::vector<cf32> rest(x.begin() + static_cast<std::ptrdiff_t>(from), x.end());
    const std::optional<Detection> d = reference ? reference_detect(rest) : detect(rest, 2000);
    if (!d) break;
    found.push_back(from + d->index);
    from += d->index + 1;
  }
  return found;
}

TEST(StsDetector, LongStrongBurstsLeaveNoResidueInTheWindowSums) {
  // A float running sum would carry the rounding of every strong sample into
  // the quiet that follows; the detector recomputes its sums instead. Over 10^6
  // samples of noise with bursts 60 dB above it (whose abrupt ends the
  // delay-and-correlate metric itself can mistake for a plateau), then a 6 dB
  // preamble, it declares exactly the packets the reference declares.
  std::mt19937 rng(7);
  std::vector<cf32> x = stream(1'000'000, 6.0, 0.05, rng);
  std::normal_distribution<float> g(0.0F, 1000.0F);
  for (std::size_t start = 1000; start + 5000 < 990'000; start += 20'000) {
    for (std::size_t i = start; i < start + 5000; ++i) x[i] = {g(rng), g(rng)};
  }
  const std::vector<std::size_t> want = all_detections(x, true);
  ASSERT_FALSE(want.empty());
  EXPECT_GE(want.back(), 1'000'000U);  // the preamble is found
  EXPECT_EQ(all_detections(x, false), want);
}

TEST(StsDetector, NoiseAloneIsNeverAPacket) {
  std::mt19937 rng(3);
  std::normal_distribution<float> g(0.0F, std::sqrt(0.5F));
  std::vector<cf32> x(500'000);
  for (cf32& s : x) s = {g(rng), g(rng)};
  EXPECT_FALSE(reference_detect(x).has_value());
  EXPECT_FALSE(detect(x, 250).has_value());
}

std::array<cf32, 64> ltf_time() {
  // The long training symbol is the second half of the L-LTF after its 32-sample GI2.
  const std::vector<cf32> frame = ppdu(1);
  std::array<cf32, 64> t{};
  std::copy_n(frame.begin() + 160 + 32, 64, t.begin());
  return t;
}

TEST(LtfSearch, FindsT1AndTheCarrierOffset) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> offset(-0.1, 0.1);
  LtfSearch search(ltf_time());
  for (int trial = 0; trial < 50; ++trial) {
    const double cfo = offset(rng);
    const std::size_t lead = 1 + rng() % 150;  // T1 at `lead` in the packet buffer
    std::vector<cf32> x = stream(1000, 30.0, cfo, rng);
    const std::vector<cf32> pkt(x.begin() + static_cast<std::ptrdiff_t>(1000 + 192 - lead),
                                x.begin() + static_cast<std::ptrdiff_t>(1000 + 192 - lead + 296));
    // The coarse estimate is off by a little; the fine one removes the rest.
    const LtfTiming t = search.find(pkt, cfo + 0.002, 160);
    EXPECT_EQ(t.t1, lead) << "trial " << trial;
    EXPECT_NEAR(t.cfo, cfo, 2e-4) << "trial " << trial;
  }
  EXPECT_THROW(search.find(std::vector<cf32>(200), 0.0, 160), std::invalid_argument);
}

}  // namespace
}  // namespace rfsitl::phy::ofdm
