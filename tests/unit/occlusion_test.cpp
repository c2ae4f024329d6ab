// The occlusion stage: a direction's loss against the cones it falls in, worked
// out by hand for each geometry (a cone under the belly, one ahead), following
// the attitude, at both ends of the link.
#include "rfsitl/channel/stages/occlusion.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <string>

#include "rfsitl/config/record.hpp"
#include "rfsitl/registry/channel_stage_registry.hpp"

#include "stage_test_support.hpp"

namespace rfsitl::channel {
namespace {

using rfsitl::testing::end;
using rfsitl::testing::link;

constexpr double kDeg = std::numbers::pi / 180.0;

config::Record sector(double azimuth, double elevation, double half_angle, double loss) {
  return config::Record{{"azimuth_deg", azimuth},
                        {"elevation_deg", elevation},
                        {"half_angle_deg", half_angle},
                        {"loss_db", loss}};
}

config::Settings with_sectors(config::Records sectors) {
  config::Settings s = find_channel_stage("occlusion")->info.defaults();
  s.set("sectors", std::move(sectors));
  return s;
}

std::unique_ptr<GainStage> make_stage(const config::Records& sectors) {
  const ChannelStageComponent* c = find_channel_stage("occlusion");
  const config::Settings s = with_sectors(sectors);
  c->info.validate(s);
  return c->make(s, StageContext{});
}

double gain_db(const GainStage& st, const LinkEnd& tx, const LinkEnd& rx) {
  return 20.0 * std::log10(std::abs(st.gain(link(tx, rx))));
}

/// One end's loss towards the other, through the belly cone of 30 deg, 20 dB.
double end_loss_db(const LinkEnd& from, const LinkEnd& to) {
  const std::vector<OcclusionSector> belly{{0.0, -90.0, 30.0, 20.0}};
  return occlusion::loss_db(belly, *direction_in_body(from, to));
}

const config::Records kBelly{sector(0, -90, 30, 20)};

TEST(Occlusion, ANodeAboveAnotherLosesTheBellyConeAtTheUpperEnd) {
  const auto stage = make_stage(kBelly);
  const LinkEnd upper = end(0, 0, 0, 100);
  const LinkEnd lower = end(1, 0, 0, 0);
  EXPECT_DOUBLE_EQ(end_loss_db(upper, lower), 20.0);  // straight down: inside
  EXPECT_DOUBLE_EQ(end_loss_db(lower, upper), 0.0);   // straight up: outside
  EXPECT_NEAR(gain_db(*stage, upper, lower), -20.0, 1e-9);
  EXPECT_NEAR(gain_db(*stage, lower, upper), -20.0, 1e-9);  // both ends count, either way
  EXPECT_FALSE(stage->reciprocal());
  EXPECT_TRUE(stage->depends_on_attitude());
}

TEST(Occlusion, LeavingTheConeRemovesTheLoss) {
  const auto stage = make_stage(kBelly);
  const LinkEnd upper = end(0, 0, 0, 100);
  // 29 and 31 deg off the vertical, 100 m down: inside and outside the cone.
  EXPECT_NEAR(gain_db(*stage, upper, end(1, 100 * std::tan(29 * kDeg), 0, 0)), -20.0, 1e-9);
  EXPECT_NEAR(gain_db(*stage, upper, end(1, 100 * std::tan(31 * kDeg), 0, 0)), 0.0, 1e-12);
  EXPECT_NEAR(gain_db(*stage, upper, end(1, 0, 500, 100)), 0.0, 1e-12);  // level
}

TEST(Occlusion, TheLossFollowsTheAttitude) {
  const auto stage = make_stage(kBelly);
  // Rolled 40 deg right wing down, the belly faces 40 deg off the vertical,
  // to the west (body z in NED: (0, -sin 40, cos 40)): straight down is now
  // outside the 30 deg cone, and a node 40 deg west of straight down inside.
  const LinkEnd rolled = end(0, 0, 0, 100, Orientation{40 * kDeg, 0, 0});
  EXPECT_NEAR(gain_db(*stage, rolled, end(1, 0, 0, 0)), 0.0, 1e-12);
  EXPECT_NEAR(gain_db(*stage, rolled, end(1, -100 * std::tan(40 * kDeg), 0, 0)), -20.0, 1e-9);

  // A cone ahead (20 deg, 6 dB): yaw decides whether a node to the east is in it.
  const auto ahead = make_stage({sector(0, 0, 20, 6)});
  const LinkEnd east = end(1, 100, 0, 50);  // level, facing north: A is at its left
  EXPECT_NEAR(gain_db(*ahead, end(0, 0, 0, 50), east), 0.0, 1e-12);
  EXPECT_NEAR(gain_db(*ahead, end(0, 0, 0, 50, Orientation{0, 0, 90 * kDeg}), east), -6.0, 1e-9);
  // No attitude counts as level, facing north: B, straight north, is ahead.
  EXPECT_NEAR(gain_db(*ahead, end(0, 0, 0, 50), end(1, 0, 100, 50)), -6.0, 1e-9);
}

TEST(Occlusion, OverlappingConesAddAndNoConeLosesNothing) {
  const LinkEnd upper = end(0, 0, 0, 100);
  const LinkEnd lower = end(1, 0, 0, 0);
  // Straight down is in both: the belly cone and a wide cone behind and below.
  EXPECT_NEAR(gain_db(*make_stage({sector(0, -90, 30, 20), sector(180, -45, 50, 3)}), upper, lower),
              -23.0, 1e-9);
  EXPECT_NEAR(gain_db(*make_stage({}), upper, lower), 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(std::abs(make_stage(kBelly)->gain(link(upper, upper))), 1.0);
}

TEST(Occlusion, SectorsAreChecked) {
  const config::ComponentInfo& info = find_channel_stage("occlusion")->info;
  EXPECT_THROW(info.validate(with_sectors({sector(0, -90, 181, 20)})), config::SettingError);
  EXPECT_THROW(info.validate(with_sectors({sector(0, -91, 30, 20)})), config::SettingError);
  EXPECT_THROW(info.validate(with_sectors({sector(0, -90, 30, -1)})), config::SettingError);
  EXPECT_THROW(info.validate(with_sectors({config::Record{{"azimuth_deg", 0}}})),
               config::SettingError);
  EXPECT_NO_THROW(info.validate(with_sectors(kBelly)));
}

}  // namespace
}  // namespace rfsitl::channel
