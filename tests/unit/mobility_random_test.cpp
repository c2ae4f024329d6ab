// The seeded models: random waypoint and Gauss-Markov. Same seed, same track
// (whatever order it is asked in); another seed, another track; never outside
// the box; velocities that are the derivative of the positions.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "mobility_test_support.hpp"
#include "rfsitl/position/mobility/gauss_markov_model.hpp"
#include "rfsitl/position/mobility/random_waypoint_model.hpp"

namespace rfsitl::position::mobility {
namespace {

using testing::near;
using testing::velocity_is_derivative;

const Box kBox{-200, 300, 0, 400, 20, 120};

RandomWaypointSettings rwp(std::uint64_t seed) {
  RandomWaypointSettings s;
  s.box = kBox;
  s.speed_min_mps = 2;
  s.speed_max_mps = 15;
  s.pause_s = 1.5;
  s.seed = seed;
  return s;
}

GaussMarkovSettings gm(std::uint64_t seed) {
  GaussMarkovSettings s;
  s.box = kBox;
  s.alpha = 0.75;
  s.mean_speed_mps = 12;
  s.mean_direction_rad = 0.3;
  s.speed_sd_mps = 3;
  s.direction_sd_rad = 0.6;
  s.pitch_sd_rad = 0.2;
  s.update_interval_s = 0.5;
  s.seed = seed;
  return s;
}

std::vector<MotionState> sample(MobilityModel& m, double step, std::size_t n) {
  std::vector<MotionState> out;
  for (std::size_t i = 0; i < n; ++i) out.push_back(m.state_at(static_cast<double>(i) * step));
  return out;
}

bool identical(const MotionState& a, const MotionState& b) {
  return a.position.x_m == b.position.x_m && a.position.y_m == b.position.y_m &&
         a.position.z_m == b.position.z_m && a.velocity.vx_mps == b.velocity.vx_mps &&
         a.velocity.vy_mps == b.velocity.vy_mps && a.velocity.vz_mps == b.velocity.vz_mps;
}

template <class Model, class Settings>
void expect_seeded_and_boxed(Settings (*make)(std::uint64_t)) {
  Model a(make(7));
  Model b(make(7));
  Model c(make(8));
  // 10^5 samples every 50 ms: 5000 s, far past the cache window of 256-512 steps.
  const auto ta = sample(a, 0.05, 100000);
  const auto tb = sample(b, 0.05, 100000);
  const auto tc = sample(c, 0.05, 100000);
  std::size_t differ = 0;
  double travelled = 0;
  for (std::size_t i = 0; i < ta.size(); ++i) {
    ASSERT_TRUE(identical(ta[i], tb[i])) << "same seed, sample " << i;
    differ += identical(ta[i], tc[i]) ? 0 : 1;
    ASSERT_TRUE(kBox.contains(ta[i].position)) << "sample " << i;
    ASSERT_TRUE(kBox.contains(tc[i].position)) << "sample " << i;
    if (i > 0)
      travelled += std::hypot(ta[i].position.x_m - ta[i - 1].position.x_m,
                              ta[i].position.y_m - ta[i - 1].position.y_m);
  }
  EXPECT_GT(differ, ta.size() * 99 / 100) << "another seed, another track";
  EXPECT_GT(travelled, 5000.0) << "the node moves (1 m/s: far below either mean speed)";

  // Asked at scattered times (back past the window too), the same answers.
  Model d(make(7));
  for (const std::size_t i : {99999u, 3u, 50000u, 50001u, 12u, 77777u, 0u, 99998u}) {
    EXPECT_TRUE(identical(d.state_at(static_cast<double>(i) * 0.05), ta[i])) << "sample " << i;
  }
  // The velocity is the derivative of the positions.
  for (double t = 0.013; t < 400; t += 3.7) EXPECT_TRUE(velocity_is_derivative(d, t));
}

TEST(MobilityRandomWaypoint, SeededReproducibleAndInsideItsBox) {
  expect_seeded_and_boxed<RandomWaypointModel>(&rwp);
}

TEST(MobilityRandomWaypoint, LegsRunAtDrawnSpeedsAndPauseAtDestinations) {
  RandomWaypointModel m(rwp(3));
  double paused = 0;
  double moving = 0;
  for (double t = 0; t < 2000; t += 0.01) {
    const Velocity v = m.state_at(t).velocity;
    const double speed = std::sqrt(v.vx_mps * v.vx_mps + v.vy_mps * v.vy_mps + v.vz_mps * v.vz_mps);
    if (speed == 0) {
      paused += 0.01;
    } else {
      moving += 0.01;
      ASSERT_GE(speed, 2 - 1e-9);
      ASSERT_LE(speed, 15 + 1e-9);
    }
  }
  EXPECT_GT(paused, 1.0);
  EXPECT_GT(moving, paused);
}

TEST(MobilityRandomWaypoint, ManyShortLegsBackPastTheCacheWindowGiveTheSameTrack) {
  // Legs of ~1 cm at 50-100 m/s: ~10^4 legs in 2 s, so the cache drops old legs
  // and a look back regenerates them from the seed.
  RandomWaypointSettings s = rwp(21);
  s.box = {0, 0.01, 0, 0.01, 5, 5};
  s.speed_min_mps = 50;
  s.speed_max_mps = 100;
  s.pause_s = 0;
  RandomWaypointModel forward(s);
  const auto track = sample(forward, 1e-4, 20000);
  RandomWaypointModel back(s);
  for (std::size_t i = track.size(); i-- > 0;) {
    ASSERT_TRUE(identical(back.state_at(static_cast<double>(i) * 1e-4), track[i])) << i;
    ASSERT_TRUE(s.box.contains(track[i].position));
  }
}

TEST(MobilityRandomWaypoint, StartsAtTheGivenPointAndHoldsItBeforeTimeZero) {
  RandomWaypointSettings s = rwp(11);
  s.start = LocalPosition{0, 0, 50};
  RandomWaypointModel m(s);
  EXPECT_TRUE(near(m.state_at(-3).position, {0, 0, 50}, 0.0));
  EXPECT_TRUE(near(m.state_at(0).position, {0, 0, 50}, 0.0));
  EXPECT_GT(std::abs(m.state_at(0).velocity.vx_mps) + std::abs(m.state_at(0).velocity.vy_mps), 0);
}

TEST(MobilityGaussMarkov, SeededReproducibleAndInsideItsBox) {
  expect_seeded_and_boxed<GaussMarkovModel>(&gm);
}

TEST(MobilityGaussMarkov, StraightLinesWithFullMemoryAndSpecularBounces) {
  // alpha = 1: no noise, constant velocity; the faces reflect it exactly.
  GaussMarkovSettings s = gm(1);
  s.alpha = 1;
  s.box = {0, 100, 0, 100, 50, 50};  // flat: z is held
  s.mean_speed_mps = 10;
  s.mean_direction_rad = std::atan2(3.0, 4.0);  // (8, 6) m/s
  s.pitch_sd_rad = 0;
  s.start = LocalPosition{20, 10, 50};
  GaussMarkovModel m(s);
  EXPECT_TRUE(near(m.state_at(5).position, {60, 40, 50}));
  EXPECT_TRUE(near(m.state_at(5).velocity, {8, 6, 0}));
  // x reaches 100 at t = 10 (y = 70), then comes back; y reaches 100 at t = 15.
  EXPECT_TRUE(near(m.state_at(12).position, {84, 82, 50}));
  EXPECT_TRUE(near(m.state_at(12).velocity, {-8, 6, 0}));
  EXPECT_TRUE(near(m.state_at(17).position, {44, 88, 50}));
  EXPECT_TRUE(near(m.state_at(17).velocity, {-8, -6, 0}));
  EXPECT_TRUE(velocity_is_derivative(m, 12.3));
}

TEST(MobilityGaussMarkov, AFaceMirrorsTheMeanHeadingSoTheNodeSweepsBackAndForth) {
  // alpha = 0, no noise: the heading is its mean at every update. Were the mean
  // not mirrored at a bounce, the node would turn back into the east face at
  // the next update and stay pinned there.
  GaussMarkovSettings s = gm(2);
  s.alpha = 0;
  s.speed_sd_mps = 0;
  s.direction_sd_rad = 0;
  s.pitch_sd_rad = 0;
  s.mean_direction_rad = 0;  // east
  s.box = {0, 100, 0, 10, 0, 0};
  s.start = LocalPosition{50, 5, 0};
  GaussMarkovModel m(s);
  int east_half = 0;
  int west_half = 0;
  for (double t = 0; t < 200; t += 0.25) {
    const MotionState st = m.state_at(t);
    (st.position.x_m > 50 ? east_half : west_half) += 1;
    ASSERT_NEAR(std::fabs(st.velocity.vx_mps), 12, 1e-9) << t;
  }
  EXPECT_NEAR(east_half, west_half, 8);  // 200 s at 12 m/s: twelve crossings
  EXPECT_TRUE(near(m.state_at(25.0 / 12).position, {75, 5, 0}));
  EXPECT_TRUE(near(m.state_at(100.0 / 12).position, {50, 5, 0}));  // back after the bounce
  EXPECT_TRUE(near(m.state_at(100.0 / 12).velocity, {-12, 0, 0}));
}

TEST(MobilityGaussMarkov, SpeedAndHeadingStayNearTheirMeans) {
  GaussMarkovSettings s = gm(5);
  s.box = {-1e6, 1e6, -1e6, 1e6, 0, 0};  // far walls: no reflection in play
  s.start = LocalPosition{0, 0, 0};
  s.direction_sd_rad = 0.2;
  s.pitch_sd_rad = 0;  // level flight: the horizontal speed is the whole speed
  GaussMarkovModel m(s);
  double speed_sum = 0;
  double east_sum = 0;
  double north_sum = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const Velocity v = m.state_at(i * s.update_interval_s).velocity;
    speed_sum += std::hypot(v.vx_mps, v.vy_mps);
    east_sum += v.vx_mps;
    north_sum += v.vy_mps;
  }
  EXPECT_NEAR(speed_sum / n, 12.0, 0.3);
  EXPECT_NEAR(std::atan2(north_sum, east_sum), 0.3, 0.05);
}

template <class Settings>
std::string refusal(const Settings& s) {
  try {
    s.validate();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

TEST(MobilityRandomSettings, RefusalsNameTheField) {
  RandomWaypointSettings r = rwp(1);
  EXPECT_EQ(refusal(r), "accepted");
  r.speed_min_mps = 0;
  EXPECT_EQ(refusal(r), "random_waypoint.speed_min_mps must be > 0 and finite (got 0)");
  r = rwp(1);
  r.speed_max_mps = 1;
  EXPECT_EQ(refusal(r),
            "random_waypoint.speed_max_mps must be >= speed_min_mps and finite (got 1)");
  r = rwp(1);
  r.box.y_max_m = -10;
  EXPECT_EQ(refusal(r), "random_waypoint.box.y_max_m must be >= y_min_m (got -10)");
  r = rwp(1);
  r.box = {5, 5, 5, 5, 5, 5};
  r.pause_s = 0;
  EXPECT_EQ(refusal(r), "random_waypoint.pause_s must be > 0 when the box is a point (got 0)");
  r = rwp(1);
  r.start = LocalPosition{1000, 0, 50};
  EXPECT_EQ(refusal(r), "random_waypoint.start must be inside random_waypoint.box");

  GaussMarkovSettings g = gm(1);
  EXPECT_EQ(refusal(g), "accepted");
  g.alpha = 1.5;
  EXPECT_EQ(refusal(g), "gauss_markov.alpha must be in [0, 1] (got 1.5)");
  g = gm(1);
  g.update_interval_s = 0;
  EXPECT_EQ(refusal(g), "gauss_markov.update_interval_s must be > 0 and finite (got 0)");
  g = gm(1);
  g.box.z_max_m = 2e5;
  EXPECT_EQ(refusal(g), "gauss_markov.box.max: z 200000 out of range [-1000, 100000]");
  g = gm(1);
  g.mean_pitch_rad = 2;
  EXPECT_EQ(refusal(g), "gauss_markov.mean_pitch_rad must be in [-pi/2, pi/2] (got 2)");
  EXPECT_THROW(GaussMarkovModel{g}, std::invalid_argument);
}

}  // namespace
}  // namespace rfsitl::position::mobility
