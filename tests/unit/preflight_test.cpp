// The preflight: it runs the scenario's first seconds in virtual time with the
// scenario's traffic or, without any, the stand-in ping load; and a scenario
// far beyond any machine (64 OFDM receivers at 20 Msps, every one run every
// tick on a channel kept busy) is called unable to hold real time, whatever
// the machine's load (a busier machine only makes it slower).
#include "rfsitl/engine/preflight.hpp"

#include <gtest/gtest.h>

#include <string>

#include "engine_run.hpp"

namespace rfsitl::engine {
namespace {

const std::vector<testing::NodeSpec> kPair{{1, LocalPosition{0, 0, 0}},
                                           {2, LocalPosition{5, 0, 0}}};

TEST(Preflight, RunsTheScenarioOrTheStandInLoadInVirtualTime) {
  scenario::Scenario s = testing::make_scenario(kPair, 60.0);
  s.timing.mode = scenario::TimeMode::kRealTime;  // as rfsitl run would start it
  const PreflightReport stand_in = preflight(s, 1.5);
  EXPECT_FALSE(stand_in.own_traffic);
  EXPECT_NEAR(stand_in.virtual_s, 1.5, 0.01);
  EXPECT_GE(stand_in.frames, 4U);  // two pings and their answers, at least
  EXPECT_GT(stand_in.speed(), 0.0);
  EXPECT_GT(stand_in.cores_needed(), 0.0);
  EXPECT_NE(stand_in.summary().find("stand-in load"), std::string::npos) << stand_in.summary();

  s.traffic.push_back(testing::frame_at(0.01, 1, 2, 40));
  s.timing.duration_s = 0.5;  // shorter than asked: the scenario's own end
  const PreflightReport own = preflight(s, 1.5);
  EXPECT_TRUE(own.own_traffic);
  EXPECT_EQ(own.frames, 1U);
  EXPECT_NEAR(own.virtual_s, 0.5, 0.01);
  EXPECT_NE(own.summary().find("the scenario's traffic"), std::string::npos) << own.summary();
}

TEST(Preflight, StopsARunThatTakesLongerThanItsWallTimeCap) {
  scenario::Scenario s = testing::make_scenario(kPair, 0.0);
  // Ten thousand virtual seconds would take minutes: the cap ends it.
  const PreflightReport r = preflight(s, 1e4, 0.2);
  EXPECT_GT(r.virtual_s, 0.0);
  EXPECT_LT(r.virtual_s, 1e4);
  EXPECT_GT(r.speed(), 0.0);
}

TEST(Preflight, SaysAHugeScenarioCannotHoldRealTime) {
  std::vector<testing::NodeSpec> nodes;
  for (NodeId id = 1; id <= 64; ++id) {
    nodes.push_back({id, LocalPosition{static_cast<double>(id % 8) * 5.0,
                                       static_cast<double>(id / 8) * 5.0, 10.0}});
  }
  scenario::Scenario s = testing::make_scenario(nodes, 0.0);
  s.timing.mode = scenario::TimeMode::kRealTime;
  s.timing.sample_rate_hz = 20e6;
  s.timing.tick_samples = 2000;
  s.phy = scenario::PhyChoice::of("ofdm");
  s.engine.skip_idle_receivers = false;  // every receiver, every tick
  for (NodeId id = 1; id <= 8; ++id) {   // and the air never quiet
    s.traffic.push_back({0.0001 * id, id, static_cast<NodeId>(id + 8), 1000, 1000, 0.0005});
  }
  const PreflightReport r = preflight(s, 0.005);
  EXPECT_LT(r.speed(), 1.0) << r.summary();
  EXPECT_GT(r.virtual_s, 0.0);
  EXPECT_NE(r.summary().find("will not hold"), std::string::npos) << r.summary();
}

}  // namespace
}  // namespace rfsitl::engine
