#include "rfsitl/monitor/spectrum.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace rfsitl::monitor {
namespace {

TEST(Spectrum, FftOfAnImpulseIsFlatAndOfAToneIsOneBin) {
  std::vector<cf32> x(64, cf32{});
  x[0] = 1.0F;
  fft_in_place(x);
  for (const cf32 v : x) EXPECT_NEAR(std::abs(v - cf32(1.0F)), 0.0F, 1e-6F);
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double ph = 2.0 * std::numbers::pi * 5.0 * static_cast<double>(i) / 64.0;
    x[i] = cf32(static_cast<float>(std::cos(ph)), static_cast<float>(std::sin(ph)));
  }
  fft_in_place(x);
  for (std::size_t k = 0; k < x.size(); ++k) {
    EXPECT_NEAR(std::abs(x[k]), k == 5 ? 64.0F : 0.0F, 1e-3F) << k;
  }
}

TEST(Spectrum, UnitPowerWhiteNoiseAveragesToZeroDbInEveryBin) {
  std::mt19937 rng(3);
  std::normal_distribution<float> g(0.0F, std::sqrt(0.5F));
  std::vector<cf32> noise(256 * 400);
  for (auto& v : noise) v = cf32(g(rng), g(rng));
  SpectrumAverager avg(256);
  avg.add(std::span(noise).first(1000));  // fed in uneven pieces
  avg.add(std::span(noise).subspan(1000));
  EXPECT_EQ(avg.blocks(), 400U);
  const auto db = avg.take_db();
  ASSERT_EQ(db.size(), 256U);
  double mean = 0;
  for (const float v : db) {
    EXPECT_NEAR(v, 0.0F, 1.5F);
    mean += v;
  }
  EXPECT_NEAR(mean / 256.0, 0.0, 0.3);
  EXPECT_TRUE(avg.take_db().empty());  // the average restarted
}

TEST(Spectrum, ToneAtAQuarterOfTheSampleRateLandsThreeQuartersAcrossAfterTheShift) {
  std::vector<cf32> tone(256 * 8);
  for (std::size_t i = 0; i < tone.size(); ++i) {
    const double ph = 2.0 * std::numbers::pi * 0.25 * static_cast<double>(i);
    tone[i] = cf32(static_cast<float>(std::cos(ph)), static_cast<float>(std::sin(ph)));
  }
  SpectrumAverager avg(256);
  avg.add(tone);
  const auto db = avg.take_db();
  const auto peak = std::max_element(db.begin(), db.end()) - db.begin();
  EXPECT_EQ(peak, 128 + 64);  // DC sits at bin 128; +fs/4 is 64 bins above it
  // A unit tone's power in its bin: N^2 sum(w)^2 / (N sum(w^2)) relative; well above noise.
  EXPECT_GT(db[static_cast<std::size_t>(peak)], 20.0F);
  EXPECT_LT(db[40], -40.0F);  // far from the tone, only window leakage
}

TEST(Spectrum, DiscardingAPartialBlockKeepsBlocksContiguous) {
  SpectrumAverager avg(8);
  const std::vector<cf32> ones(6, cf32(1.0F));
  avg.add(ones);
  avg.discard_partial_block();  // a gap: those 6 samples must not start a block
  avg.add(ones);
  EXPECT_EQ(avg.blocks(), 0U);
  avg.add(ones);
  EXPECT_EQ(avg.blocks(), 1U);
}

}  // namespace
}  // namespace rfsitl::monitor
