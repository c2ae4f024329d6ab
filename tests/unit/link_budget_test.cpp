// The link budget and the channel matrix over spy stages: how a chain's kinds
// of stage are combined and when each is evaluated.
#include "rfsitl/channel/link_budget.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <memory>

#include "rfsitl/channel/channel_matrix.hpp"
#include "rfsitl/common/geodesy.hpp"
#include "spy_gain_stage.hpp"

namespace rfsitl::channel {
namespace {

using rfsitl::testing::SpyGainStage;
using Calls = std::shared_ptr<std::atomic<int>>;

const GeodeticPosition kOrigin{43.0, -78.8, 0.0};

Calls counter() {
  return std::make_shared<std::atomic<int>>(0);
}

/// A gain that names the link: 1 / (1 + 10 tx + rx), so each direction differs.
std::complex<double> by_indices(const LinkGeometry& g) {
  return 1.0 / (1.0 + 10.0 * static_cast<double>(g.tx.index) + static_cast<double>(g.rx.index));
}

std::shared_ptr<const LinkBudget> budget_of(double fixed_db, std::unique_ptr<GainStage> a,
                                            std::unique_ptr<GainStage> b = nullptr) {
  std::vector<std::unique_ptr<GainStage>> stages;
  stages.push_back(std::move(a));
  if (b) stages.push_back(std::move(b));
  return std::make_shared<const LinkBudget>(fixed_db, std::move(stages));
}

TEST(LinkBudget, TheFixedGainAndTheStagesMultiply) {
  const auto b = budget_of(20.0,
                           std::make_unique<SpyGainStage>([](const LinkGeometry&) { return 0.01; },
                                                          SpyGainStage::Traits{}, counter()),
                           std::make_unique<SpyGainStage>(
                               [](const LinkGeometry&) { return std::complex<double>(0, 0.5); },
                               SpyGainStage::Traits{}, counter()));
  // 20 dBm: amplitude 10; then 0.01 and 0.5 j.
  const cf32 c = b->coefficient(LinkGeometry{});
  EXPECT_NEAR(c.real(), 0.0, 1e-9);
  EXPECT_NEAR(c.imag(), 10.0 * 0.01 * 0.5, 1e-7);
}

TEST(LinkBudget, TimeVaryingStagesAreKeptOutOfTheLargeScaleCoefficient) {
  const Calls fading_calls = counter();
  const auto b = budget_of(
      0.0,
      std::make_unique<SpyGainStage>([](const LinkGeometry&) { return 0.5; },
                                     SpyGainStage::Traits{}, counter()),
      std::make_unique<SpyGainStage>([](const LinkGeometry&) { return std::complex<double>(0, 2); },
                                     SpyGainStage::Traits{false, true, false, 1e-3}, fading_calls));
  EXPECT_TRUE(b->time_varying());
  EXPECT_DOUBLE_EQ(b->update_interval_s(), 1e-3);
  EXPECT_TRUE(b->reciprocal());  // only the large-scale stages count
  EXPECT_EQ(b->coefficient(LinkGeometry{}), (cf32{0.5F, 0.0F}));
  EXPECT_EQ(fading_calls->load(), 0);
  EXPECT_EQ(b->fading(LinkGeometry{}), std::complex<double>(0, 2));
  EXPECT_EQ(fading_calls->load(), 1);
}

TEST(ChannelMatrixOverStages, ANonReciprocalStageIsEvaluatedInBothDirections) {
  ChannelMatrix m(3,
                  budget_of(0.0, std::make_unique<SpyGainStage>(
                                     by_indices, SpyGainStage::Traits{false}, counter())),
                  kOrigin);
  for (std::size_t i = 0; i < 3; ++i) {
    m.set_position(i, local_to_ecef({static_cast<double>(i), 0.0, 0.0}, kOrigin));
  }
  for (std::size_t tx = 0; tx < 3; ++tx) {
    for (std::size_t rx = 0; rx < 3; ++rx) {
      LinkGeometry g;
      g.tx.index = tx;
      g.rx.index = rx;
      EXPECT_FLOAT_EQ(m.coefficient(tx, rx).real(), static_cast<float>(by_indices(g).real()))
          << tx << "->" << rx;
    }
  }
}

TEST(ChannelMatrixOverStages, TurningReevaluatesOnlyForStagesThatCareAboutAttitude) {
  for (const bool cares : {false, true}) {
    const Calls calls = counter();
    ChannelMatrix m(
        2,
        budget_of(0.0, std::make_unique<SpyGainStage>(
                           by_indices, SpyGainStage::Traits{true, false, cares}, calls)),
        kOrigin);
    m.set_position(0, local_to_ecef({0.0, 0.0, 0.0}, kOrigin));
    m.set_position(1, local_to_ecef({5.0, 0.0, 0.0}, kOrigin));
    const int before = calls->load();
    m.set_attitude(1, Orientation{0.0, 0.0, 1.0});
    m.set_attitude(1, Orientation{0.0, 0.0, 1.0});  // the same again: nothing to do
    EXPECT_EQ(calls->load() > before, cares);
    EXPECT_EQ(calls->load() - before, cares ? 2 : 0);  // node 1's two links, once
  }
}

TEST(ChannelMatrixOverStages, TimeVaryingGainsSeeTheEndsExtrapolatedAlongTheirVelocity) {
  // The spy returns the transmitter's east coordinate as the gain.
  const auto east = [](const LinkGeometry& g) { return std::complex<double>(g.tx.local.x_m, 0); };
  ChannelMatrix m(
      2,
      budget_of(0.0, std::make_unique<SpyGainStage>(
                         east, SpyGainStage::Traits{true, true, false, 1e-3}, counter())),
      kOrigin);
  m.set_clock(2.0);
  m.set_position(0, local_to_ecef({10.0, 0.0, 0.0}, kOrigin));
  m.set_position(1, local_to_ecef({0.0, 0.0, 0.0}, kOrigin));
  m.set_velocity(0, LocalVelocity{3.0, 0.0, 0.0});
  // 0.5 s after the position was set, at 3 m/s east: 11.5 m.
  EXPECT_NEAR(m.coefficient_at(0, 1, 2.5).real(), 11.5, 1e-4);
  EXPECT_NEAR(m.coefficient_at(0, 1, 2.0).real(), 10.0, 1e-4);
}

}  // namespace
}  // namespace rfsitl::channel
