// The channel as the engine calls it: mixing through the links, the noise, and
// the front end's gain, for one receiver at a time.
#include "rfsitl/channel/channel.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <vector>

#include "rfsitl/channel/stages/path_loss.hpp"
#include "rfsitl/common/geodesy.hpp"

namespace rfsitl::channel {
namespace {

const GeodeticPosition kOrigin{43.0, -78.8, 0.0};

Channel three_in_a_row(double noise_variance) {
  Channel ch(3, make_paper_budget(1.0), kOrigin, ChannelConfig{noise_variance, false, 7, 1e6, 64});
  for (std::size_t i = 0; i < 3; ++i) {
    ch.matrix().set_position(i, local_to_ecef({3.0 * static_cast<double>(i), 0.0, 0.0}, kOrigin));
  }
  return ch;
}

TEST(Channel, AReceiverGetsTheGainTimesTheLinksSumAndNotItself) {
  // Noise 1e-4: the front end's gain is 100.
  Channel ch = three_in_a_row(1e-4);
  ASSERT_NEAR(ch.front_end_gain(), 100.0, 1e-9);
  const std::size_t b = 64, first = 10;
  std::vector<cf32> x0(b, cf32{1.0F, 0.0F}), x1(b, cf32{0.0F, 2.0F}), x2(b, cf32{-1.0F, 1.0F});
  const std::vector<Transmission> active{{0, x0.data()}, {1, x1.data()}, {2, x2.data()}};
  std::vector<cf32> y(b - first);
  Channel::Scratch scratch;
  ch.on_air(0, active);
  ch.receive(1, first, y, scratch);
  // Paper model, exponent 1: c = (1+j)/sqrt2 / (d + 1), d = 3 m to both neighbours.
  const std::complex<double> c = std::complex<double>(1.0, 1.0) / std::sqrt(2.0) / 4.0;
  const std::complex<double> want =
      100.0 * c * (std::complex<double>(1.0, 0.0) + std::complex<double>(-1.0, 1.0));
  // The noise, 100 x sqrt(1e-4) = unit power per sample, averages out over the
  // 54 samples: the mean is within 6 sigma (6 / sqrt(54)) of the signal.
  std::complex<double> mean = 0.0;
  for (const cf32 v : y) mean += std::complex<double>(v);
  mean /= static_cast<double>(y.size());
  EXPECT_LT(std::abs(mean - want), 6.0 / std::sqrt(54.0)) << mean << " vs " << want;
}

TEST(Channel, SilenceIsTheNoiseAtUnitPowerWhateverItsVariance) {
  for (const double variance : {1e-12, 1e-3}) {
    Channel ch = three_in_a_row(variance);
    std::vector<cf32> y(64);
    Channel::Scratch scratch;
    double power = 0.0;
    for (SampleTime tick = 0; tick < 64 * 200; tick += 64) {
      ch.on_air(tick, {});
      ch.receive(0, 0, y, scratch);
      for (const cf32 v : y) power += std::norm(v);
    }
    // 12800 samples of unit-power complex noise: the mean power's standard
    // deviation is 1 / sqrt(12800) = 0.009.
    EXPECT_NEAR(power / 12800.0, 1.0, 0.06) << variance;
  }
}

TEST(Channel, TheNoiseIsAFunctionOfTheSampleTimeNotOfTheCallOrder) {
  Channel ch = three_in_a_row(1e-6);
  Channel::Scratch scratch;
  std::vector<cf32> whole(64), late(54);
  ch.on_air(128, {});
  ch.receive(2, 0, whole, scratch);
  ch.receive(2, 10, late, scratch);
  for (std::size_t t = 0; t < late.size(); ++t) EXPECT_EQ(late[t], whole[10 + t]) << t;
}

TEST(Channel, ReceiversMixedTogetherGetExactlyWhatEachGetsAlone) {
  // 30 nodes on a line, all on the air (above the engine's threshold for
  // grouping), receivers in groups of 1..4: each group's inputs, noise
  // included, equal receive() for each receiver alone, bit for bit.
  constexpr std::size_t kNodes = 30, kB = 250;
  Channel ch(kNodes, make_paper_budget(2.0), kOrigin, ChannelConfig{1e-6, false, 11, 1e6, kB});
  for (std::size_t i = 0; i < kNodes; ++i) {
    ch.matrix().set_position(i, local_to_ecef({5.0 * static_cast<double>(i), 0.0, 0.0}, kOrigin));
  }
  std::vector<std::vector<cf32>> x(kNodes, std::vector<cf32>(kB));
  std::vector<Transmission> active;
  for (std::size_t n = 0; n < kNodes; ++n) {
    for (std::size_t t = 0; t < kB; ++t) {
      x[n][t] = cf32{std::sin(0.1F * static_cast<float>(t + n)),
                     std::cos(0.3F * static_cast<float>(t * n))};
    }
    active.push_back({n, x[n].data()});
  }
  ch.on_air(4 * kB, active);
  ch.begin_tick(4 * kB, true);
  ASSERT_TRUE(ch.mixes_together(kNodes));
  EXPECT_FALSE(ch.mixes_together(kNodes + 1));
  Channel::Scratch scratch;
  for (std::size_t size = 1; size <= Channel::kMaxTogether; ++size) {
    for (std::size_t m0 = 0; m0 + size <= kNodes; m0 += size) {
      std::vector<std::size_t> ms;
      std::vector<std::vector<cf32>> together(size, std::vector<cf32>(kB));
      std::vector<cf32*> ys;
      for (std::size_t j = 0; j < size; ++j) {
        ms.push_back(m0 + j);
        ys.push_back(together[j].data());
      }
      ch.receive_together(ms, ys, scratch);
      for (std::size_t j = 0; j < size; ++j) {
        std::vector<cf32> alone(kB);
        ch.receive(ms[j], 0, alone, scratch);
        ASSERT_EQ(together[j], alone) << "group of " << size << ", receiver " << ms[j];
      }
    }
  }
}

}  // namespace
}  // namespace rfsitl::channel
