// Velocity from positions alone (location port, dashboard): exact for the first
// difference, settling on a constant velocity, smoothing jitter, and starting
// over after silence.
#include <gtest/gtest.h>

#include <cmath>

#include "rfsitl/common/xoshiro256.hpp"
#include "rfsitl/position/source/velocity_estimator.hpp"

namespace rfsitl::position {
namespace {

TEST(VelocityEstimator, TheFirstReportGivesZeroAndTheFirstDifferenceIsExact) {
  VelocityEstimator e;
  const Velocity v0 = e.update(1.0, {10, 20, 30});
  EXPECT_EQ(v0, Velocity{});
  const Velocity v1 = e.update(1.5, {12, 19, 30.5});
  EXPECT_DOUBLE_EQ(v1.vx_mps, 4.0);
  EXPECT_DOUBLE_EQ(v1.vy_mps, -2.0);
  EXPECT_DOUBLE_EQ(v1.vz_mps, 1.0);
}

TEST(VelocityEstimator, BlendsLaterDifferencesWithWeightOneMinusExpOfDtOverTau) {
  VelocityEstimator e(2.0);
  e.update(0.0, {0, 0, 0});
  e.update(1.0, {5, 0, 0});                     // 5 m/s
  const Velocity v = e.update(2.0, {6, 0, 0});  // then 1 m/s
  const double w = 1.0 - std::exp(-1.0 / 2.0);
  EXPECT_NEAR(v.vx_mps, 5.0 + w * (1.0 - 5.0), 1e-12);
}

TEST(VelocityEstimator, SettlesOnAConstantVelocityDespiteJitter) {
  VelocityEstimator e;  // tau 1 s
  Xoshiro256 rng(7);
  Velocity v;
  for (int k = 0; k <= 100; ++k) {  // 10 s at 10 Hz, 1 m/s east, 2 m/s up, +-5 cm noise
    const double t = 0.1 * k;
    const double jitter = 0.1 * (static_cast<double>(rng.next() >> 11) * 0x1p-53 - 0.5);
    v = e.update(t, {1.0 * t + jitter, 0.0, 2.0 * t});
  }
  // One report's jitter alone would be up to 0.5 m/s off; smoothed, far less.
  EXPECT_NEAR(v.vx_mps, 1.0, 0.15);
  EXPECT_NEAR(v.vz_mps, 2.0, 1e-9);
  EXPECT_NEAR(v.vy_mps, 0.0, 1e-12);
}

TEST(VelocityEstimator, ASecondReportAtTheSameInstantReplacesTheFirst) {
  VelocityEstimator e;
  e.update(1.0, {0, 0, 0});
  e.update(1.0, {100, 0, 0});  // no time passed: not 'infinite speed'
  const Velocity v = e.update(2.0, {101, 0, 0});
  EXPECT_DOUBLE_EQ(v.vx_mps, 1.0);
}

TEST(VelocityEstimator, AJumpAfterSilenceIsARelocationNotMotion) {
  VelocityEstimator e(1.0, 5.0);
  e.update(0.0, {0, 0, 0});
  e.update(1.0, {3, 0, 0});
  const Velocity v = e.update(20.0, {5000, 0, 0});
  EXPECT_EQ(v, Velocity{});
  EXPECT_DOUBLE_EQ(e.update(21.0, {5002, 0, 0}).vx_mps, 2.0);
}

}  // namespace
}  // namespace rfsitl::position
