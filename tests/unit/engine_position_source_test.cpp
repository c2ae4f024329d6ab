// The engine as the sink of live position sources, on test doubles: a report
// moves its node (applied at the next tick); a velocity that comes with it is kept as
// reported, and positions alone get one estimated on the engine's clock; the
// stats show the node's position, motion and source.
#include <gtest/gtest.h>

#include "engine_run.hpp"
#include "rfsitl/common/geodesy.hpp"
#include "rfsitl/monitor/stats_report.hpp"
#include "scripted_position_source.hpp"

namespace rfsitl::testing {
namespace {

using position::StateReport;

StateReport at(double x, double y, double z) {
  StateReport r;
  r.position = LocalPosition{x, y, z};
  return r;
}

TEST(EnginePositionSource, ReportsMoveNodesWithTheirMotion) {
  scenario::Scenario s = make_scenario({{1, std::nullopt}, {2, std::nullopt}}, 2.0);
  StateReport full = at(100, 0, 10);
  full.velocity = position::Velocity{1, 2, 3};
  full.attitude = position::Attitude{0.1, 0.2, 0.3};
  ScriptedPositionSource source({{0.5, 1, full}, {1.0, 0, at(0, 0, 10)}, {1.5, 0, at(5, 0, 10)}});
  RunSetup setup;
  setup.before = [&](engine::Engine& e) { source.start(e); };
  const double fs = s.timing.sample_rate_hz;
  TickHook hook(fs, [&](double t) { source.advance(t); });
  setup.observers = {&hook};
  const RunResult r = run_engine(s, setup);
  const auto positions = r.engine->positions();
  ASSERT_TRUE(positions[1]);
  const LocalPosition p2 = ecef_to_local(*positions[1], s.channel.origin);
  EXPECT_NEAR(p2.x_m, 100.0, 1e-6);
  EXPECT_NEAR(p2.z_m, 10.0, 1e-6);
  const auto motions = r.engine->motions();
  // Reported velocity and attitude, as reported.
  EXPECT_EQ(motions[1].velocity, (position::Velocity{1, 2, 3}));
  EXPECT_EQ(motions[1].attitude, (position::Attitude{0.1, 0.2, 0.3}));
  // Positions alone, 5 m in 0.5 s of engine time apart: 10 m/s east.
  ASSERT_TRUE(motions[0].velocity);
  EXPECT_NEAR(motions[0].velocity->vx_mps, 10.0, 1e-9);
  EXPECT_NEAR(motions[0].velocity->vy_mps, 0.0, 1e-9);
  EXPECT_FALSE(motions[0].attitude);

  const auto stats = monitor::stats_json(s, *r.engine, [&](std::size_t i) {
    return std::optional<position::SourceStatus>(
        position::SourceStatus{"script", source.where(i), *source.counters(i), std::nullopt});
  });
  const auto& n1 = stats.at("nodes").at(0);
  EXPECT_EQ(n1.at("source").at("type"), "script");
  EXPECT_EQ(n1.at("source").at("updates"), 2);
  EXPECT_DOUBLE_EQ(n1.at("position").at("x").get<double>(), 5.0);
  EXPECT_DOUBLE_EQ(n1.at("velocity").at("east_mps").get<double>(), 10.0);
  EXPECT_DOUBLE_EQ(stats.at("nodes").at(1).at("attitude").at("yaw_rad").get<double>(), 0.3);
}

}  // namespace
}  // namespace rfsitl::testing
